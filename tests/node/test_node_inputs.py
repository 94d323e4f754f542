"""The node's image and pose inputs through an in-memory transport, for both wire formats
(ROS 1 serialisation, ROS 2 CDR): the same frame as mono8, rgb8, bgr8, mono16 and a PNG
CompressedImage gives the same scan as `floorscan scan` on the grey frame; poses from TF
(odom -> base_link) place the scans like nav_msgs/Odometry does."""

from __future__ import annotations

import time

import numpy as np
import pytest
from floorscan import GroundTable
from floorscan.formats.image_io import read_grey
from floorscan.formats.rosbag import ROSBAGS_MISSING
from floorscan.node import NodeRun
from floorscan.node.messages import Codec
from floorscan.pipeline.config import Config
from floorscan.ranging.ranger import VisualRanger
from node_loopback import LoopbackTransport
from synthetic_dataset import camera_table, make_dataset


@pytest.fixture(scope="module")
def room(tmp_path_factory):
    d = tmp_path_factory.mktemp("inputs")
    make_dataset(d / "room", n=2)
    camera_table().save(d / "table.json")
    return d


def header(T, t, frame):
    sec = int(t)
    kw = dict(
        stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=int(round((t - sec) * 1e9))),
        frame_id=frame,
    )
    if "seq" in T["std_msgs/msg/Header"].__dataclass_fields__:
        kw["seq"] = 0
    return T["std_msgs/msg/Header"](**kw)


def image(codec, t, pixels, encoding):
    T = codec.types
    h, w = pixels.shape[:2]
    data = np.ascontiguousarray(pixels)
    if encoding == "mono16":
        data = data.astype("<u2")
    return codec.serialize(
        T["sensor_msgs/msg/Image"](
            header=header(T, t, "camera"),
            height=h,
            width=w,
            encoding=encoding,
            is_bigendian=0,
            step=data.strides[0],
            data=data.view(np.uint8).ravel(),
        ),
        "sensor_msgs/msg/Image",
    )


def compressed(codec, t, grey):
    import cv2

    ok, buf = cv2.imencode(".png", grey)
    T = codec.types
    return codec.serialize(
        T["sensor_msgs/msg/CompressedImage"](
            header=header(T, t, "camera"), format="png", data=buf.ravel()
        ),
        "sensor_msgs/msg/CompressedImage",
    )


def run_node(room, tmp_path, ros_version, node_toml, messages, n):
    cfg = Config.from_toml(
        '[ranger]\nthreshold = 20.0\n[outputs]\noverlay = "none"\nbag = false\n' + node_toml
    )
    tr = LoopbackTransport(ros_version)
    node = NodeRun(
        GroundTable.load(room / "table.json"), cfg, tmp_path / "out", transport=tr, max_frames=n
    )
    import threading

    runner = threading.Thread(target=node.run)
    runner.start()
    for topic, data in messages:
        tr.send(topic, data)
        time.sleep(0.05)
    runner.join(30)
    assert not runner.is_alive()
    codec = Codec(ros_version)
    return [codec.deserialize(b, "sensor_msgs/msg/LaserScan") for b in tr.published["/scan"]], node


@pytest.mark.parametrize("ros_version", [1, 2])
def test_every_encoding_gives_floorscan_scans_ranges(room, tmp_path, ros_version):
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the node's messages
    grey = read_grey(room / "room" / "images" / "000000.png")
    rgb = np.repeat(grey[..., None], 3, axis=2)
    codec = Codec(ros_version)
    raw = [
        image(codec, 100.0, grey, "mono8"),
        image(codec, 100.0, rgb, "rgb8"),
        image(codec, 100.0, rgb[..., ::-1], "bgr8"),
        image(codec, 100.0, grey.astype(np.uint16) * 257, "mono16"),
    ]
    scans, _ = run_node(
        room,
        tmp_path / "raw",
        ros_version,
        '[node]\nodom_topic = ""\n',
        [("/camera/image_raw", m) for m in raw],
        len(raw),
    )
    comp, _ = run_node(
        room,
        tmp_path / "png",
        ros_version,
        '[node]\nodom_topic = ""\ncompressed = true\n',
        [("/camera/image_raw", compressed(codec, 100.0, grey))],
        1,
    )
    ref = VisualRanger(GroundTable.load(room / "table.json"), threshold=20.0).scan(
        grey, timestamp=100.0
    )
    assert len(scans) == 4 and len(comp) == 1
    for laser in scans[:3] + comp:
        want = ref.to_laser_scan(
            angle_min=laser.angle_min,
            angle_max=laser.angle_max,
            angle_increment=laser.angle_increment,
        )
        np.testing.assert_array_equal(laser.ranges, np.asarray(want["ranges"], np.float32))
    # mono16: the same picture at 257x the intensity; the threshold scales with it, so the
    # boundary rows are the same where the 8-bit edge was clear: compare with the ranger on it.
    ref16 = VisualRanger(GroundTable.load(room / "table.json"), threshold=20.0).scan(
        grey.astype(np.uint16) * 257, timestamp=100.0
    )
    want = ref16.to_laser_scan(
        angle_min=scans[3].angle_min,
        angle_max=scans[3].angle_max,
        angle_increment=scans[3].angle_increment,
    )
    np.testing.assert_array_equal(scans[3].ranges, np.asarray(want["ranges"], np.float32))


def odometry(codec, t, x, y, yaw):
    T = codec.types
    z = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
    return codec.serialize(
        T["nav_msgs/msg/Odometry"](
            header=header(T, t, "odom"),
            child_frame_id="base_link",
            pose=T["geometry_msgs/msg/PoseWithCovariance"](
                pose=codec._pose((x, y, yaw)), covariance=np.zeros(36)
            ),
            twist=T["geometry_msgs/msg/TwistWithCovariance"](
                twist=T["geometry_msgs/msg/Twist"](linear=z, angular=z), covariance=np.zeros(36)
            ),
        ),
        "nav_msgs/msg/Odometry",
    )


def tf(codec, t, x, y, yaw, parent="odom", child="base_link"):
    T = codec.types
    tf = T["geometry_msgs/msg/TransformStamped"](
        header=header(T, t, parent),
        child_frame_id=child,
        transform=T["geometry_msgs/msg/Transform"](
            translation=T["geometry_msgs/msg/Vector3"](x=x, y=y, z=0.0),
            rotation=codec._pose((0, 0, yaw)).orientation,
        ),
    )
    return codec.serialize(T["tf2_msgs/msg/TFMessage"](transforms=[tf]), "tf2_msgs/msg/TFMessage")


@pytest.mark.parametrize("ros_version", [1, 2])
def test_poses_from_tf_build_the_map_odometry_builds(room, tmp_path, ros_version):
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the node's messages
    from floorscan.formats.trajectory import read_tum

    codec = Codec(ros_version)
    odo = read_tum(room / "room" / "odometry.txt")
    lines = [ln.split() for ln in (room / "room" / "images.txt").read_text().split("\n")[1:] if ln]
    frames = [(float(t), read_grey(room / "room" / p)) for t, p in lines]

    def messages(pose_msg, topic):
        out = []
        for t, x, y, yaw in zip(odo.timestamps, odo.x, odo.y, odo.yaw):
            out.append((topic, pose_msg(codec, float(t), float(x), float(y), float(yaw))))
            out += [
                ("/camera/image_raw", image(codec, ft, g, "mono8")) for ft, g in frames if ft == t
            ]
        return out

    via_odom, a = run_node(
        room, tmp_path / "odom", ros_version, "[node]\n", messages(odometry, "/odom"), len(frames)
    )
    # TF: the wanted transform among others (another child, a leading slash on the parent).
    other = [("/tf", tf(codec, 100.0, 9.0, 9.0, 1.0, child="camera"))]
    via_tf, b = run_node(
        room,
        tmp_path / "tf",
        ros_version,
        '[node]\nodom_source = "tf"\n',
        other + messages(lambda c, t, x, y, yaw: tf(c, t, x, y, yaw, parent="/odom"), "/tf"),
        len(frames),
    )
    assert a.mapper.frames == b.mapper.frames == len(frames)
    assert np.array_equal(a.mapper.global_map.raw(), b.mapper.global_map.raw())
    assert np.count_nonzero(a.mapper.global_map.raw()) > 100


@pytest.mark.parametrize("ros_version", [1, 2])
def test_the_node_publishes_map_to_odom_each_frame(room, tmp_path, ros_version):
    """REP 105 / slam_toolbox: ``map -> odom`` on /tf is the scan matcher's correction (the
    last frame's equals the mapper's), identity with [slam] off, absent when the maps are in
    the odometry frame; the maps are published in the map frame."""
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the node's messages
    import math

    from floorscan.formats.trajectory import read_tum, yaw_from_quaternion
    from floorscan.node.messages import OCCUPANCY_GRID, TF_MESSAGE

    codec = Codec(ros_version)
    odo = read_tum(room / "room" / "odometry.txt")
    lines = [ln.split() for ln in (room / "room" / "images.txt").read_text().split("\n")[1:] if ln]
    frames = [(float(t), read_grey(room / "room" / p)) for t, p in lines]
    messages = []
    for t, x, y, yaw in zip(odo.timestamps, odo.x, odo.y, odo.yaw):
        messages.append(("/odom", odometry(codec, float(t), float(x), float(y), float(yaw) + 0.05)))
        messages += [
            ("/camera/image_raw", image(codec, ft, g, "mono8")) for ft, g in frames if ft == t
        ]

    def published(node_toml, name):
        cfg = Config.from_toml(
            '[ranger]\nthreshold = 20.0\n[outputs]\noverlay = "none"\nbag = false\n' + node_toml
        )
        tr = LoopbackTransport(ros_version)
        node = NodeRun(
            GroundTable.load(room / "table.json"),
            cfg,
            tmp_path / name,
            transport=tr,
            max_frames=len(frames),
        )
        import threading

        runner = threading.Thread(target=node.run)
        runner.start()
        for topic, data in messages:
            tr.send(topic, data)
            time.sleep(0.05)
        runner.join(30)
        assert not runner.is_alive()
        tfs = [codec.deserialize(b, TF_MESSAGE).transforms for b in tr.published.get("/tf", [])]
        maps = [codec.deserialize(b, OCCUPANCY_GRID) for b in tr.published["/map"]]
        return node, tfs, maps

    node, tfs, maps = published("[node]\n", "local")
    assert node.mapper.slam is not None and len(tfs) == node.mapper.frames == len(frames)
    assert all(
        len(t) == 1 and t[0].header.frame_id == "map" and t[0].child_frame_id == "odom" for t in tfs
    )
    last = tfs[-1][0].transform
    q = last.rotation
    got = (last.translation.x, last.translation.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
    want = node.mapper.slam.map_from_odom
    assert got[:2] == pytest.approx(want[:2], abs=1e-9)
    assert math.remainder(got[2] - want[2], 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    assert maps and all(m.header.frame_id == "map" for m in maps)

    node, tfs, _ = published('[slam]\nmode = "off"\n[node]\n', "off")
    assert node.mapper.slam is None and len(tfs) == len(frames)
    for (t,) in tfs:
        assert (t.transform.translation.x, t.transform.translation.y, t.transform.rotation.w) == (
            0.0,
            0.0,
            1.0,
        )

    _, tfs, maps = published('[node]\nmap_frame = "odom"\n', "odom")
    assert tfs == [] and all(m.header.frame_id == "odom" for m in maps)
