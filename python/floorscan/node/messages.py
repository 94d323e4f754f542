"""The node's messages as bytes, both ways, with rosbags' codecs (no ROS install): ROS 1
serialisation for the rospy transport, CDR (with its 4-byte encapsulation header) for ROS 2.

Names are ROS 2 style (``sensor_msgs/msg/LaserScan``) for both; :meth:`Codec.md5sum` and
:meth:`Codec.type_hash` give the ROS 1 MD5 sum and the ROS 2 RIHS01 type hash (REP 2016).
"""

from __future__ import annotations

from typing import Dict, List, Tuple

import numpy as np

from ..errors import ImageError, MiddlewareError
from ..formats.rosbag import ROSBAGS_MISSING, _header, _time, decode_image
from ..formats.trajectory import quaternion_from_yaw, yaw_from_quaternion

IMAGE = "sensor_msgs/msg/Image"
COMPRESSED_IMAGE = "sensor_msgs/msg/CompressedImage"
ODOMETRY = "nav_msgs/msg/Odometry"
LASER_SCAN = "sensor_msgs/msg/LaserScan"
OCCUPANCY_GRID = "nav_msgs/msg/OccupancyGrid"
TF_MESSAGE = "tf2_msgs/msg/TFMessage"

TF_MSG_DEFINITION = "geometry_msgs/TransformStamped[] transforms"

OdomSample = Tuple[float, float, float, float]
"""(t [s], x [m], y [m], yaw [rad]) of ``world_from_robot``."""


class Codec:
    """Encodes and decodes the node's messages for one ROS version (1 or 2)."""

    def __init__(self, ros_version: int) -> None:
        try:
            from rosbags.typesys import Stores, get_typestore
        except ImportError:
            raise MiddlewareError(
                f"the node's messages are encoded with rosbags: {ROSBAGS_MISSING}"
            ) from None

        if ros_version not in (1, 2):
            raise ValueError(f"ros_version must be 1 or 2, got {ros_version}")
        self.ros_version = ros_version
        self.store = get_typestore(Stores.ROS1_NOETIC if ros_version == 1 else Stores.LATEST)
        if TF_MESSAGE not in self.store.types:  # rosbags' Noetic store lacks tf2_msgs
            from rosbags.typesys import get_types_from_msg

            self.store.register(get_types_from_msg(TF_MSG_DEFINITION, TF_MESSAGE))
        self.types = self.store.types
        if ros_version == 1:
            self._ser, self._de = self.store.serialize_ros1, self.store.deserialize_ros1
        else:
            self._ser, self._de = self.store.serialize_cdr, self.store.deserialize_cdr
        self._md5: Dict[str, Tuple[str, str]] = {}

    # --- type identity ----------------------------------------------------------------
    def md5sum(self, msgtype: str) -> str:
        """ROS 1 MD5 sum of a message type (what rospy checks when connecting)."""
        return self.definition(msgtype)[1]

    def definition(self, msgtype: str) -> Tuple[str, str]:
        """(full message definition text, MD5 sum) as ROS 1 connection headers carry them."""
        if msgtype not in self._md5:
            self._md5[msgtype] = self.store.generate_msgdef(msgtype, ros_version=1)
        return self._md5[msgtype]

    def type_hash(self, msgtype: str) -> str:
        """ROS 2 type hash ``RIHS01_<sha256 hex>`` (REP 2016)."""
        return self.store.hash_rihs01(msgtype)

    # --- raw -------------------------------------------------------------------------
    def serialize(self, msg, msgtype: str) -> bytes:
        return bytes(self._ser(msg, msgtype))

    def deserialize(self, data: bytes, msgtype: str):
        return self._de(memoryview(data), msgtype)

    # --- inputs ------------------------------------------------------------------------
    def decode_image(self, data: bytes, msgtype: str) -> Tuple[float, np.ndarray]:
        """(header stamp [s], grey image) of an Image / CompressedImage; ImageError on an
        unknown encoding or a message that does not parse."""
        try:
            msg = self.deserialize(data, msgtype)
        except Exception as e:  # rosbags raises several types on truncated data
            raise ImageError(f"cannot deserialise {msgtype}: {e}") from None
        # live: stderr is not redirected while decoding (the transport's threads log there)
        return _stamp(msg), decode_image(msg, msgtype, catch_decoder=False)

    def decode_odometry(self, data: bytes) -> OdomSample:
        msg = self.deserialize(data, ODOMETRY)
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        return _stamp(msg), float(p.x), float(p.y), yaw_from_quaternion(q.x, q.y, q.z, q.w)

    def decode_tf(self, data: bytes, parent: str, child: str) -> List[OdomSample]:
        """The ``parent_from_child`` poses in a ``tf2_msgs/TFMessage`` (frame ids compared
        without a leading ``/``, as tf2 does)."""
        msg = self.deserialize(data, TF_MESSAGE)
        out = []
        for tf in msg.transforms:
            if (tf.header.frame_id.lstrip("/"), tf.child_frame_id.lstrip("/")) != (parent, child):
                continue
            p, q = tf.transform.translation, tf.transform.rotation
            out.append(
                (_stamp(tf), float(p.x), float(p.y), yaw_from_quaternion(q.x, q.y, q.z, q.w))
            )
        return out

    # --- outputs -----------------------------------------------------------------------
    def laser_scan(self, t: float, laser: Dict[str, object], frame_id: str) -> bytes:
        """``sensor_msgs/LaserScan`` from :meth:`floorscan.Scan.to_laser_scan`'s bins."""
        msg = self.types[LASER_SCAN](
            header=_header(self.types, t, frame_id),
            angle_min=float(laser["angle_min"]),
            angle_max=float(laser["angle_max"]),
            angle_increment=float(laser["angle_increment"]),
            time_increment=0.0,
            scan_time=0.0,
            range_min=float(laser["range_min"]),
            range_max=float(laser["range_max"]),
            ranges=np.asarray(laser["ranges"], dtype=np.float32),
            intensities=np.zeros(0, dtype=np.float32),
        )
        return self.serialize(msg, LASER_SCAN)

    def rgb_image(self, t: float, rgb: np.ndarray, frame_id: str) -> bytes:
        """``sensor_msgs/Image`` rgb8 of an (H, W, 3) uint8 array."""
        h, w = rgb.shape[:2]
        msg = self.types[IMAGE](
            header=_header(self.types, t, frame_id),
            height=h,
            width=w,
            encoding="rgb8",
            is_bigendian=0,
            step=3 * w,
            data=np.ascontiguousarray(rgb, dtype=np.uint8).ravel(),
        )
        return self.serialize(msg, IMAGE)

    def occupancy_grid(
        self, t: float, data: np.ndarray, resolution_m: float, origin_xy_yaw, frame_id: str
    ) -> bytes:
        """``nav_msgs/OccupancyGrid``; ``data`` (H, W) int8, row 0 at the map's bottom."""
        T = self.types
        h, w = data.shape
        msg = T[OCCUPANCY_GRID](
            header=_header(T, t, frame_id),
            info=T["nav_msgs/msg/MapMetaData"](
                map_load_time=_time(T, t),
                resolution=float(resolution_m),
                width=w,
                height=h,
                origin=self._pose(origin_xy_yaw),
            ),
            data=np.ascontiguousarray(data, dtype=np.int8).ravel(),
        )
        return self.serialize(msg, OCCUPANCY_GRID)

    def transform(self, t: float, parent: str, child: str, xy_yaw) -> bytes:
        """``tf2_msgs/TFMessage`` with one transform ``parent_from_child`` (x, y, yaw), as
        ``/tf`` and ``/tf_static`` carry them."""
        T = self.types
        qx, qy, qz, qw = quaternion_from_yaw(float(xy_yaw[2]))
        tf = T["geometry_msgs/msg/TransformStamped"](
            header=_header(T, t, parent),
            child_frame_id=child,
            transform=T["geometry_msgs/msg/Transform"](
                translation=T["geometry_msgs/msg/Vector3"](
                    x=float(xy_yaw[0]), y=float(xy_yaw[1]), z=0.0
                ),
                rotation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
            ),
        )
        return self.serialize(T[TF_MESSAGE](transforms=[tf]), TF_MESSAGE)

    def _pose(self, xy_yaw):
        T = self.types
        qx, qy, qz, qw = quaternion_from_yaw(float(xy_yaw[2]))
        return T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=float(xy_yaw[0]), y=float(xy_yaw[1]), z=0.0),
            orientation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
        )


def _stamp(msg) -> float:
    s = msg.header.stamp
    return s.sec + s.nanosec * 1e-9
