"""The middleware seen by ``floorscan node``: a small interface with two implementations,
ROS 1 through rospy (:mod:`.ros1`) and ROS 2 through rmw_zenoh's protocol (:mod:`.zenoh`).

A transport moves serialised messages (bytes in the ROS version's own wire format, see
:class:`~floorscan.node.messages.Codec`); it knows topic names and type names, never the
content. Callbacks run on the transport's own threads and must only hand the bytes over.
"""

from __future__ import annotations

import abc
from typing import Callable, Optional

Callback = Callable[[bytes, float], None]
"""Called with (message bytes, receive time from ``time.perf_counter()`` [s])."""


class Publisher(abc.ABC):
    @abc.abstractmethod
    def publish(self, data: bytes) -> None:
        """Sends one serialised message."""

    def subscriber_count(self) -> Optional[int]:
        """How many subscribers are connected (None when the middleware cannot tell)."""
        return None


class Transport(abc.ABC):
    """One node on one middleware."""

    ros_version: int = 0

    @abc.abstractmethod
    def subscribe(self, topic: str, msgtype: str, callback: Callback) -> None:
        """Calls ``callback`` for every message on ``topic`` of type ``msgtype``."""

    @abc.abstractmethod
    def advertise(self, topic: str, msgtype: str, *, latched: bool = False) -> Publisher:
        """A publisher; ``latched``: late subscribers get the last message (ROS 1 latch,
        ROS 2 transient-local durability)."""

    def health(self) -> Optional[str]:
        """None while the middleware works, else why not (e.g. the ROS master is gone)."""
        return None

    @abc.abstractmethod
    def close(self) -> None:
        """Leaves the graph (idempotent)."""
