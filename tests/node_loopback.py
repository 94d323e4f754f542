"""An in-memory Transport for the node's tests: subscriptions are callbacks the test calls with
serialised messages, publications are recorded per topic (no middleware)."""

from __future__ import annotations

import time

from floorscan.node.transport import Publisher, Transport


class LoopbackTransport(Transport):
    def __init__(self, ros_version: int = 2) -> None:
        self.ros_version = ros_version
        self.callbacks, self.published = {}, {}

    def subscribe(self, topic, msgtype, callback):
        self.callbacks[topic] = callback

    def advertise(self, topic, msgtype, *, latched=False):
        store = self.published.setdefault(topic, [])

        class P(Publisher):
            def publish(self, data):
                store.append(data)

        return P()

    def send(self, topic: str, data: bytes) -> None:
        self.callbacks[topic](data, time.perf_counter())

    def close(self):
        pass
