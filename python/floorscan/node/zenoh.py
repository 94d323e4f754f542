"""ROS 2 transport without a ROS install: speaks rmw_zenoh's protocol (see
:mod:`.rmw_zenoh_keys`) with the ``eclipse-zenoh`` package and rosbags' CDR codec, so nodes
running ``RMW_IMPLEMENTATION=rmw_zenoh_cpp`` (ROS 2 Jazzy, Kilted, Rolling) see floorscan's
topics and floorscan receives theirs.

Like rmw_zenoh's default session it is a peer that connects to the router on
``tcp/localhost:7447`` (``node.zenoh_connect``) with multicast scouting off. Latched topics
(the maps, /tf_static) are TRANSIENT_LOCAL: an advanced publisher with a one-sample cache.
"""

from __future__ import annotations

import json
import os
import threading
import time
from typing import List, Optional

from ..errors import MiddlewareError
from . import rmw_zenoh_keys as K
from .messages import Codec
from .transport import Callback, Publisher, Transport


def import_zenoh():
    try:
        import zenoh
    except ImportError:
        raise MiddlewareError(
            "the zenoh transport needs eclipse-zenoh: pip install 'floorscan[ros2]'"
        ) from None
    return zenoh


class _ZenohPublisher(Publisher):
    def __init__(self, pub, gid: bytes) -> None:
        self._pub = pub
        self._gid = gid
        self._seq = 1  # rmw_zenoh's publishers count from 1
        self._lock = threading.Lock()

    def publish(self, data: bytes) -> None:
        with self._lock:
            att = K.attachment(self._seq, time.time_ns(), self._gid)
            self._seq += 1
            self._pub.put(data, attachment=att)


class ZenohTransport(Transport):
    ros_version = 2

    def __init__(
        self,
        node_name: str,
        *,
        domain_id: int = 0,
        mode: str = "peer",
        connect: Optional[str] = "tcp/localhost:7447",
        listen: Optional[str] = None,
        namespace: str = "/",
    ) -> None:
        zenoh = self.zenoh = import_zenoh()
        self.codec = Codec(2)
        self.domain_id = domain_id
        self.node_name = node_name
        self.namespace = namespace
        conf = zenoh.Config()
        conf.insert_json5("mode", json.dumps(mode))
        conf.insert_json5("scouting/multicast/enabled", "false")
        conf.insert_json5("timestamping/enabled", "true")  # advanced publishers need it
        conf.insert_json5("connect/endpoints", json.dumps([connect] if connect else []))
        if listen:
            conf.insert_json5("listen/endpoints", json.dumps([listen]))
        try:
            self.session = zenoh.open(conf)
        except Exception as e:  # zenoh.ZError: bad endpoint, no router in client mode, ...
            raise MiddlewareError(f"cannot open a zenoh session ({mode}, {connect}): {e}") from None
        self.zid = str(self.session.info.zid())
        self._connect = connect
        self._health: Optional[str] = None
        self._health_at = -1e9
        self._next_entity = 1
        self._node_id = 0
        self._tokens: List[object] = []
        self._entities: List[object] = []
        self._closed = False
        self._declare_token(K.node_token(domain_id, self.zid, 0, node_name, namespace))

    def _declare_token(self, key: str) -> None:
        self._tokens.append(self.session.liveliness().declare_token(key))

    def _entity(self, kind: str, topic: str, msgtype: str, qos: K.Qos) -> str:
        eid, self._next_entity = self._next_entity, self._next_entity + 1
        h = self.codec.type_hash(msgtype)
        token = K.endpoint_token(
            self.domain_id,
            self.zid,
            self._node_id,
            eid,
            kind,
            self.node_name,
            topic,
            msgtype,
            h,
            qos,
            self.namespace,
        )
        self._declare_token(token)
        return K.topic_keyexpr(self.domain_id, self._resolve(topic), msgtype, h)

    def _resolve(self, topic: str) -> str:
        if topic.startswith("/") or self.namespace in ("", "/"):
            return topic
        return f"{self.namespace.rstrip('/')}/{topic}"

    def subscribe(self, topic: str, msgtype: str, callback: Callback) -> None:
        key = self._entity("MS", topic, msgtype, K.SENSOR_QOS)

        def on_sample(sample) -> None:
            callback(sample.payload.to_bytes(), time.perf_counter())

        self._entities.append(self.session.declare_subscriber(key, on_sample))

    def advertise(self, topic: str, msgtype: str, *, latched: bool = False) -> Publisher:
        qos = K.LATCHED_QOS if latched else K.SENSOR_QOS
        key = self._entity("MP", topic, msgtype, qos)
        if latched:
            from zenoh import ext

            pub = ext.declare_advanced_publisher(
                self.session,
                key,
                cache=ext.CacheConfig(max_samples=qos.depth),
                publisher_detection=True,
            )
        else:
            pub = self.session.declare_publisher(key)
        self._entities.append(pub)
        return _ZenohPublisher(pub, os.urandom(K.GID_SIZE))

    def health(self) -> Optional[str]:
        """Checked once a second: a session that reaches no router and no peer says so."""
        now = time.monotonic()
        if now - self._health_at >= 1.0:
            self._health_at = now
            info = self.session.info
            alone = not list(info.routers_zid()) and not list(info.peers_zid())
            self._health = (
                f"no zenoh router or peer reached ({self._connect or 'no connect endpoint'})"
                if alone
                else None
            )
        return self._health

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        for e in self._entities + self._tokens:
            try:
                e.undeclare()
            except Exception:  # already gone with the session
                pass
        self.session.close()
