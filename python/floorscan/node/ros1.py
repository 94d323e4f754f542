"""ROS 1 transport through rospy, in this process.

rospy is pure Python; Debian ships it (``apt-get install python3-rospy``) for Debian's own
``/usr/bin/python3``. A virtual environment on the same Python minor version can import it
when that folder is on its path: :func:`import_rospy` appends ``/usr/lib/python3/dist-packages``
(last, so the environment's own numpy etc. win) only when rospy is not importable already, and
only for this transport. Messages cross rospy as bytes (classes built from rosbags' definitions
and MD5 sums), so no ``python3-sensor-msgs`` or catkin workspace is needed.
"""

from __future__ import annotations

import os
import sys
import threading
from typing import Optional

from ..errors import MiddlewareError
from .messages import Codec
from .transport import Callback, Publisher, Transport

DEBIAN_DIST_PACKAGES = "/usr/lib/python3/dist-packages"
MASTER_POLL_S = 1.0


def import_rospy():
    """rospy, from this environment or Debian's packages; MiddlewareError if neither has it."""
    try:
        import rospy
    except ImportError:
        if not os.path.isdir(os.path.join(DEBIAN_DIST_PACKAGES, "rospy")):
            raise MiddlewareError(
                "the ros1 transport needs rospy: apt-get install python3-rospy (Debian), "
                "or run in a ROS 1 environment"
            ) from None
        sys.path.append(DEBIAN_DIST_PACKAGES)
        try:
            import rospy
        except ImportError as e:
            raise MiddlewareError(f"cannot import rospy from {DEBIAN_DIST_PACKAGES}: {e}") from None
    return rospy


def ros1_name(msgtype: str) -> str:
    """``sensor_msgs/msg/LaserScan`` -> ``sensor_msgs/LaserScan``."""
    pkg, _, name = msgtype.split("/")
    return f"{pkg}/{name}"


def raw_message_class(codec: Codec, msgtype: str):
    """A rospy message class carrying already serialised bytes, with the real type name,
    MD5 sum and definition (so rospy's type check with other nodes works)."""
    import genpy

    text, md5 = codec.definition(msgtype)

    class Raw(genpy.Message):
        _type = ros1_name(msgtype)
        _md5sum = md5
        _full_text = text
        _has_header = False  # rospy must not touch the header: the bytes are final
        __slots__ = ["_buff"]

        def __init__(self, buff: bytes = b"") -> None:
            self._buff = buff

        def serialize(self, buff) -> None:
            buff.write(self._buff)

        def deserialize(self, data):
            self._buff = bytes(data)
            return self

    Raw.__name__ = f"Raw_{msgtype.replace('/', '_')}"
    return Raw


class _Ros1Publisher(Publisher):
    def __init__(self, pub, cls) -> None:
        self._pub, self._cls = pub, cls

    def publish(self, data: bytes) -> None:
        self._pub.publish(self._cls(data))

    def subscriber_count(self) -> Optional[int]:
        return self._pub.get_num_connections()


class Ros1Transport(Transport):
    """A rospy node named ``node_name`` on the master of ``ROS_MASTER_URI``."""

    ros_version = 1

    def __init__(self, node_name: str) -> None:
        self.rospy = rospy = import_rospy()
        self.codec = Codec(1)
        uri = os.environ.get("ROS_MASTER_URI", "http://localhost:11311")
        self._master_error: Optional[str] = None
        if not self._master_online():
            raise MiddlewareError(f"no ROS master at {uri} (start roscore, or set ROS_MASTER_URI)")
        # disable_signals: floorscan's own handlers stop the node and save the map.
        rospy.init_node(node_name, anonymous=False, disable_signals=True)
        self._subs, self._pubs = [], []
        self._closed = threading.Event()
        self._watch = threading.Thread(target=self._watch_master, daemon=True)
        self._watch.start()

    def _master_online(self) -> bool:
        import rosgraph

        return bool(rosgraph.is_master_online())

    def _watch_master(self) -> None:
        uri = os.environ.get("ROS_MASTER_URI", "http://localhost:11311")
        while not self._closed.wait(MASTER_POLL_S):
            online = self._master_online()
            self._master_error = None if online else f"the ROS master at {uri} is not answering"

    def subscribe(self, topic: str, msgtype: str, callback: Callback) -> None:
        import time

        cls = raw_message_class(self.codec, msgtype)

        def on_message(msg) -> None:
            callback(msg._buff, time.perf_counter())

        self._subs.append(
            self.rospy.Subscriber(topic, cls, on_message, queue_size=1, buff_size=1 << 24)
        )

    def advertise(self, topic: str, msgtype: str, *, latched: bool = False) -> Publisher:
        cls = raw_message_class(self.codec, msgtype)
        pub = self.rospy.Publisher(topic, cls, queue_size=10, latch=latched)
        self._pubs.append(pub)
        return _Ros1Publisher(pub, cls)

    def health(self) -> Optional[str]:
        return self._master_error

    def close(self) -> None:
        if self._closed.is_set():
            return
        self._closed.set()
        for s in self._subs:
            s.unregister()
        for p in self._pubs:
            p.unregister()
        self.rospy.signal_shutdown("floorscan node stopped")
