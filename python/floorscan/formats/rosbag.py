"""ROS 1 and ROS 2 bags without a ROS install (the ``rosbags`` package).

Reading: ``sensor_msgs/Image`` or ``sensor_msgs/CompressedImage`` frames and
``nav_msgs/Odometry`` poses from topics chosen by name. Writing: ``sensor_msgs/LaserScan`` scans
and ``nav_msgs/OccupancyGrid`` maps into a ROS 2 bag (sqlite3 or MCAP), and image + odometry
bags (ROS 1 or 2) for converting datasets.
"""

from __future__ import annotations

import contextlib
import importlib.util
import math
import os
import shutil
import tempfile
from pathlib import Path
from typing import Dict, Iterable, Iterator, List, Sequence, Tuple

import numpy as np

from .._atomic import PathLike, deferred_signals
from ..errors import DatasetError, FloorscanError, ImageError
from .image_io import as_grey, check_image_size, open_image
from .native_messages import native_messages
from .trajectory import Trajectory, quaternion_from_yaw, yaw_from_quaternion

IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")
ODOMETRY_TYPE = "nav_msgs/msg/Odometry"


ROSBAGS_MISSING = "the `rosbags` package is not installed (pip install rosbags)"


def rosbags_installed() -> bool:
    """True when rosbags can be imported (a dependency of floorscan, yet a missing one costs
    only the bags: ``floorscan run`` then writes everything else)."""
    try:
        return importlib.util.find_spec("rosbags") is not None
    except ImportError:
        return False


def _rosbags():
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise DatasetError(f"reading ROS bags needs {ROSBAGS_MISSING}") from None
    return AnyReader, Stores, get_typestore


def _stamp_s(msg, bag_time_ns: int) -> float:
    stamp = getattr(getattr(msg, "header", None), "stamp", None)
    if stamp is not None and (stamp.sec or stamp.nanosec):
        return stamp.sec + stamp.nanosec * 1e-9
    return bag_time_ns * 1e-9


def _check_compressed_size(data: bytes) -> None:
    """Reads a compressed image's size from its header (PIL parses the headers of PNG, JPEG,
    TIFF, WebP, BMP, PNM ... without decoding) and refuses it before OpenCV allocates the
    pixels. A format PIL cannot size (Radiance HDR, OpenEXR, PFM: OpenCV would decode them
    whole, gigabytes from a small message) is refused too: its size cannot be checked."""
    import io

    try:
        im = open_image(io.BytesIO(data), "compressed image message")
    except ImageError as e:
        if "pixels, more than the limit" in str(e) or "decompression bomb" in str(e).lower():
            raise
        raise ImageError(
            "compressed image message in a format whose size cannot be checked before "
            f"decoding ({_magic(data)}): use png or jpeg"
        ) from None
    im.close()


def _magic(data: bytes) -> str:
    head = bytes(data[:8])
    return "starts " + (head.hex(" ") if head else "empty")


def decode_image(msg, msgtype: str, *, catch_decoder: bool = True) -> np.ndarray:
    """A ROS image message as a (H, W) uint8/uint16 grey array. ``catch_decoder``: a
    compressed image's decoder complaints (libpng, libjpeg) are caught from the process's
    stderr and make the image an ImageError (a bag read by ``run``); False leaves stderr alone
    (the live node, where another thread's log lines must not be caught with them)."""
    if msgtype.endswith("CompressedImage"):
        import cv2

        data = bytes(msg.data)
        _check_compressed_size(data)
        with native_messages() if catch_decoder else contextlib.nullcontext() as said:
            # libpng / libjpeg print their complaints on the process's stderr
            img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
        if img is None or said:
            # a decoder's complaint is an error, as for image files: a corrupt JPEG decodes
            # "whole" with grey where its data was missing
            why = f": {said.first}" if said else ""
            raise ImageError(f"cannot decode compressed image (format {msg.format!r}){why}")
        if img.ndim == 3:
            img = img[..., ::-1]  # OpenCV decodes to BGR
        return as_grey(img)
    enc = msg.encoding.lower()
    data = np.frombuffer(bytes(msg.data), np.uint8)
    h, w, step = msg.height, msg.width, msg.step
    channels = {
        "mono8": 1,
        "8uc1": 1,
        "mono16": 1,
        "16uc1": 1,
        "rgb8": 3,
        "bgr8": 3,
        "rgba8": 4,
        "bgra8": 4,
    }
    if enc not in channels:
        raise ImageError(
            f"unsupported image encoding {msg.encoding!r} (mono8, mono16, rgb8, bgr8, rgba8, bgra8)"
        )
    check_image_size(int(w), int(h), "image message")
    wide = enc in ("mono16", "16uc1")
    if len(data) < h * step:
        raise ImageError(f"image message holds {len(data)} bytes, needs {h * step}")
    rows = data[: h * step].reshape(h, step)
    if wide:
        dtype = np.dtype(">u2" if msg.is_bigendian else "<u2")
        return rows[:, : 2 * w].copy().view(dtype).astype(np.uint16).reshape(h, w)
    c = channels[enc]
    img = rows[:, : w * c].reshape(h, w, c) if c > 1 else rows[:, :w]
    if enc.startswith("bgr"):
        img = img[..., [2, 1, 0]]
    return as_grey(np.ascontiguousarray(img))


def bag_topics(path: PathLike) -> Dict[str, str]:
    AnyReader, Stores, get_typestore = _rosbags()
    with _open_reader(path, AnyReader, Stores, get_typestore) as reader:
        return {c.topic: c.msgtype for c in reader.connections}


@contextlib.contextmanager
def _open_reader(path, AnyReader, Stores, get_typestore):
    """An open bag reader; any failure of the reader (damaged, truncated or empty bags, a
    corrupt metadata.yaml or database) is a DatasetError naming the bag."""
    p = Path(path)
    if not p.exists():
        raise DatasetError(f"bag not found: {p}")
    try:
        reader = AnyReader(
            [p],
            default_typestore=get_typestore(
                Stores.ROS1_NOETIC if p.suffix == ".bag" else Stores.LATEST
            ),
        )
        reader.open()
    except Exception as e:  # rosbags raises several unrelated types for damaged bags
        raise DatasetError(f"cannot open bag {p}: {e}") from None
    try:
        yield reader
    except FloorscanError:
        raise
    except (GeneratorExit, KeyboardInterrupt):
        raise
    except Exception as e:  # reading a damaged message stream
        raise DatasetError(f"cannot read bag {p}: {e}") from None
    finally:
        try:
            reader.close()
        except Exception:
            pass


def _connection(reader, topic: str, allowed: Sequence[str], path: PathLike):
    conns = [c for c in reader.connections if c.topic == topic]
    if not conns:
        have = ", ".join(sorted({f"{c.topic} ({c.msgtype})" for c in reader.connections})) or "none"
        raise DatasetError(f"bag {path} has no topic {topic!r}; topics: {have}")
    if conns[0].msgtype not in allowed:
        raise DatasetError(
            f"topic {topic!r} has type {conns[0].msgtype}, expected one of {', '.join(allowed)}"
        )
    return conns


def read_bag_odometry(path: PathLike, *, odom_topic: str) -> Trajectory:
    """The ``nav_msgs/Odometry`` poses of a topic as a planar trajectory (header stamps)."""
    AnyReader, Stores, get_typestore = _rosbags()
    rows: List[Tuple[float, float, float, float]] = []
    with _open_reader(path, AnyReader, Stores, get_typestore) as reader:
        conns = _connection(reader, odom_topic, (ODOMETRY_TYPE,), path)
        for conn, t_ns, raw in reader.messages(connections=conns):
            msg = reader.deserialize(raw, conn.msgtype)
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            rows.append((_stamp_s(msg, t_ns), p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)))
    rows.sort(key=lambda r: r[0])
    dedup = [r for i, r in enumerate(rows) if i == 0 or r[0] > rows[i - 1][0]]
    return Trajectory.from_poses(dedup)


def iter_bag_images(path: PathLike, *, image_topic: str) -> Iterator[Tuple[float, np.ndarray]]:
    """(timestamp [s], grey image or None, error or None) of every image message on a topic,
    in bag order: a message that cannot be decoded gives None and the reason."""
    AnyReader, Stores, get_typestore = _rosbags()
    with _open_reader(path, AnyReader, Stores, get_typestore) as reader:
        conns = _connection(reader, image_topic, IMAGE_TYPES, path)
        for conn, t_ns, raw in reader.messages(connections=conns):
            try:
                msg = reader.deserialize(raw, conn.msgtype)
                t = _stamp_s(msg, t_ns)
            except Exception as e:  # one damaged message: skipped and counted by the caller
                yield t_ns * 1e-9, None, f"cannot deserialise message: {e}"
                continue
            try:
                yield t, decode_image(msg, conn.msgtype), None
            except FloorscanError as e:
                yield t, None, str(e)


# --- writing ------------------------------------------------------------------------------


def _time(types, t: float):
    sec = int(math.floor(t))
    return types["builtin_interfaces/msg/Time"](
        sec=sec, nanosec=int(round((t - sec) * 1e9)) % 1_000_000_000
    )


def _header(types, t: float, frame_id: str):
    cls = types["std_msgs/msg/Header"]
    if "seq" in getattr(cls, "__dataclass_fields__", {}):  # ROS 1 headers carry a sequence number
        return cls(seq=0, stamp=_time(types, t), frame_id=frame_id)
    return cls(stamp=_time(types, t), frame_id=frame_id)


class Ros2BagWriter:
    """Writes a ROS 2 bag into a temporary folder and moves it into place on :meth:`close`
    (so a crash never leaves half a bag where a good one was)."""

    def __init__(self, path: PathLike, *, storage: str = "sqlite3") -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.typesys import Stores, get_typestore

        if storage not in ("sqlite3", "mcap"):
            raise DatasetError(f"bag storage must be 'sqlite3' or 'mcap', got {storage!r}")
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._tmpdir = Path(tempfile.mkdtemp(prefix=f".{self.path.name}.", dir=self.path.parent))
        try:
            self.typestore = get_typestore(Stores.LATEST)
            self.types = self.typestore.types
            plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
            self._writer = Writer(self._tmpdir / "bag", version=9, storage_plugin=plugin)
            self._writer.open()
        except BaseException:  # interrupted or failed while opening: leave nothing behind
            shutil.rmtree(self._tmpdir, ignore_errors=True)
            raise
        self._connections: Dict[str, object] = {}

    def _conn(self, topic: str, msgtype: str):
        if topic not in self._connections:
            self._connections[topic] = self._writer.add_connection(
                topic, msgtype, typestore=self.typestore
            )
        return self._connections[topic]

    def write(self, topic: str, msgtype: str, t: float, msg) -> None:
        data = self.typestore.serialize_cdr(msg, msgtype)
        self._writer.write(self._conn(topic, msgtype), int(round(t * 1e9)), data)

    def write_laser_scan(
        self,
        t: float,
        laser: Dict[str, object],
        *,
        topic: str = "/scan",
        frame_id: str = "camera_ground",
    ) -> None:
        ranges = np.asarray(laser["ranges"], dtype=np.float32)
        msg = self.types["sensor_msgs/msg/LaserScan"](
            header=_header(self.types, t, frame_id),
            angle_min=float(laser["angle_min"]),
            angle_max=float(laser["angle_max"]),
            angle_increment=float(laser["angle_increment"]),
            time_increment=0.0,
            scan_time=0.0,
            range_min=float(laser["range_min"]),
            range_max=float(laser["range_max"]),
            ranges=ranges,
            intensities=np.zeros(0, dtype=np.float32),
        )
        self.write(topic, "sensor_msgs/msg/LaserScan", t, msg)

    def write_occupancy_grid(
        self,
        t: float,
        data: np.ndarray,
        *,
        resolution_m: float,
        origin_xy_yaw: Tuple[float, float, float],
        topic: str = "/map",
        frame_id: str = "map",
    ) -> None:
        """``data``: (H, W) int8, -1 unknown, 0..100; row 0 is the map's bottom (y = origin)."""
        T = self.types
        h, w = data.shape
        qx, qy, qz, qw = quaternion_from_yaw(origin_xy_yaw[2])
        origin = T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](
                x=float(origin_xy_yaw[0]), y=float(origin_xy_yaw[1]), z=0.0
            ),
            orientation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
        )
        info = T["nav_msgs/msg/MapMetaData"](
            map_load_time=_time(T, t),
            resolution=float(resolution_m),
            width=w,
            height=h,
            origin=origin,
        )
        msg = T["nav_msgs/msg/OccupancyGrid"](
            header=_header(T, t, frame_id),
            info=info,
            data=np.ascontiguousarray(data, dtype=np.int8).ravel(),
        )
        self.write(topic, "nav_msgs/msg/OccupancyGrid", t, msg)

    def close(self) -> Path:
        self._writer.close()
        if self.path.exists():
            shutil.rmtree(self.path)
        os.replace(self._tmpdir / "bag", self.path)
        shutil.rmtree(self._tmpdir, ignore_errors=True)
        return self.path

    def abort(self) -> None:
        """Drops the unfinished bag and its temporary folder (a signal meanwhile is delivered
        once the folder is gone)."""
        with deferred_signals():
            try:
                self._writer.close()
            finally:
                shutil.rmtree(self._tmpdir, ignore_errors=True)


def write_image_odometry_bag(
    path: PathLike,
    frames: Iterable[Tuple[float, np.ndarray]],
    odometry: Trajectory,
    *,
    ros_version: int = 2,
    image_topic: str = "/camera/image_raw",
    odom_topic: str = "/odom",
    compressed: bool = False,
) -> Path:
    """Writes grey frames (``sensor_msgs/Image`` mono8, or ``CompressedImage`` PNG) and odometry
    (``nav_msgs/Odometry``) into a ROS 1 (``.bag`` file) or ROS 2 (folder) bag."""
    from rosbags.typesys import Stores, get_typestore

    path = Path(path)
    if path.exists():
        raise DatasetError(f"{path} exists already; bags are never overwritten")
    frames = list(frames)
    times = [t for t, _ in frames] + [float(t) for t in odometry.timestamps]
    if times and min(times) < 0:
        # Checked before the bag is created, so a bad input leaves no half-written bag.
        raise DatasetError(f"bag message times must be >= 0 s (ROS time), got {min(times)}")
    ts = get_typestore(Stores.ROS1_NOETIC if ros_version == 1 else Stores.LATEST)
    T = ts.types
    if ros_version == 1:
        from rosbags.rosbag1 import Writer

        writer = Writer(path)
        serialize = ts.serialize_ros1
    elif ros_version == 2:
        from rosbags.rosbag2 import Writer

        writer = Writer(path, version=9)
        serialize = ts.serialize_cdr
    else:
        raise DatasetError(f"ros_version must be 1 or 2, got {ros_version}")
    img_type = "sensor_msgs/msg/CompressedImage" if compressed else "sensor_msgs/msg/Image"
    with writer:
        ci = writer.add_connection(image_topic, img_type, typestore=ts)
        co = writer.add_connection(odom_topic, ODOMETRY_TYPE, typestore=ts)
        msgs = []
        for t, img in frames:
            grey = np.ascontiguousarray(as_grey(img), dtype=np.uint8)
            if compressed:
                import cv2

                ok, buf = cv2.imencode(".png", grey)
                m = T[img_type](header=_header(T, t, "camera"), format="png", data=buf.ravel())
            else:
                h, w = grey.shape
                m = T[img_type](
                    header=_header(T, t, "camera"),
                    height=h,
                    width=w,
                    encoding="mono8",
                    is_bigendian=0,
                    step=w,
                    data=grey.ravel(),
                )
            msgs.append((t, ci, img_type, m))
        for t, x, y, yaw in zip(odometry.timestamps, odometry.x, odometry.y, odometry.yaw):
            qx, qy, qz, qw = quaternion_from_yaw(float(yaw))
            pose = T["geometry_msgs/msg/PoseWithCovariance"](
                pose=T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=0.0),
                    orientation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
                ),
                covariance=np.zeros(36),
            )
            twist = T["geometry_msgs/msg/TwistWithCovariance"](
                twist=T["geometry_msgs/msg/Twist"](
                    linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                    angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                ),
                covariance=np.zeros(36),
            )
            m = T[ODOMETRY_TYPE](
                header=_header(T, float(t), "odom"),
                child_frame_id="base_link",
                pose=pose,
                twist=twist,
            )
            msgs.append((float(t), co, ODOMETRY_TYPE, m))
        for t, conn, typ, m in sorted(msgs, key=lambda r: r[0]):
            writer.write(conn, int(round(t * 1e9)), serialize(m, typ))
    return path
