"""The ROS 2 transport: rmw_zenoh's names checked against the examples of its design document
(ros2/rmw_zenoh docs/design.md), then `floorscan node` over Zenoh with a second session in this
process as the robot: it publishes the synthetic room's frames as a ROS 2 node would (CDR, keys,
attachments), and the scans that come back must equal `floorscan scan`'s."""

from __future__ import annotations

import json
import struct
import threading
import time

import numpy as np
import pytest
from floorscan import GroundTable, read_scans_csv
from floorscan.cli import main
from floorscan.formats.rosbag import ROSBAGS_MISSING
from floorscan.pipeline.config import Config
from ros1_fixtures import free_port
from synthetic_dataset import camera_table, make_dataset

zenoh = pytest.importorskip(
    "zenoh", reason="eclipse-zenoh is not installed (pip install eclipse-zenoh)"
)
pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the node's messages

from floorscan.node import NodeRun  # noqa: E402
from floorscan.node import rmw_zenoh_keys as K  # noqa: E402
from floorscan.node.messages import Codec  # noqa: E402

# Verbatim from rmw_zenoh's docs/design.md (Jazzy): the std_msgs/String type hash, the
# talker's publisher token and the listener's node token.
STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
TALKER_TOKEN = (
    "@ros2_lv/0/8b20917502ee955ac4476e0266340d5c/0/10/MP/%/%/talker/%chatter/"
    f"std_msgs::msg::dds_::String_/{STRING_HASH}/::,7:,:,:,,"
)
LISTENER_NODE = "@ros2_lv/0/aac3178e146ba6f1fc6e6a4085e77f21/0/0/NN/%/%/listener"
CHATTER_KEY = f"0/chatter/std_msgs::msg::dds_::String_/{STRING_HASH}"


def test_names_match_the_design_document():
    codec = Codec(2)
    assert codec.type_hash("std_msgs/msg/String") == STRING_HASH
    assert K.topic_keyexpr(0, "/chatter", "std_msgs/msg/String", STRING_HASH) == CHATTER_KEY
    assert K.node_token(0, "aac3178e146ba6f1fc6e6a4085e77f21", 0, "listener") == LISTENER_NODE
    token = K.endpoint_token(
        0,
        "8b20917502ee955ac4476e0266340d5c",
        0,
        10,
        "MP",
        "talker",
        "/chatter",
        "std_msgs/msg/String",
        STRING_HASH,
        K.Qos(depth=7),
    )
    assert token == TALKER_TOKEN
    # Namespaced names are mangled slash by slash.
    ns = K.endpoint_token(
        3,
        "ab",
        0,
        2,
        "MS",
        "n",
        "/robot1/scan",
        "sensor_msgs/msg/LaserScan",
        "H",
        K.Qos(depth=5),
        namespace="/robot1",
    )
    assert (
        ns
        == "@ros2_lv/3/ab/0/2/MS/%/%robot1/n/%robot1%scan/sensor_msgs::msg::dds_::LaserScan_/H/::,5:,:,:,,"
    )
    assert K.Qos(durability=K.TRANSIENT_LOCAL, depth=1).keyexpr() == ":1:,1:,:,:,,"
    assert K.Qos(reliability=K.BEST_EFFORT, depth=5).keyexpr() == "2::,5:,:,:,,"


def test_attachment_is_zenohs_serialisation_of_seq_time_gid():
    from zenoh.ext import Int64, z_serialize

    gid = bytes(range(100, 116))
    ours = K.attachment(7, 1_700_000_000_123_456_789, gid)
    assert ours == z_serialize((Int64(7), Int64(1_700_000_000_123_456_789), gid)).to_bytes()
    assert len(ours) == 33 and K.parse_attachment(ours) == (7, 1_700_000_000_123_456_789, gid)
    assert K.parse_attachment(ours[:-1]) is None


@pytest.fixture(scope="module")
def room(tmp_path_factory):
    d = tmp_path_factory.mktemp("zenoh_ds")
    make_dataset(d / "room", n=15)
    camera_table().save(d / "table.json")
    return d


def ros2_image(codec, t, grey):
    T = codec.types
    sec = int(t)
    msg = T["sensor_msgs/msg/Image"](
        header=T["std_msgs/msg/Header"](
            stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=int(round((t - sec) * 1e9))),
            frame_id="camera",
        ),
        height=grey.shape[0],
        width=grey.shape[1],
        encoding="mono8",
        is_bigendian=0,
        step=grey.shape[1],
        data=grey.ravel(),
    )
    return codec.serialize(msg, "sensor_msgs/msg/Image")


def test_node_over_zenoh_answers_every_frame_with_floorscan_scans_ranges(room, tmp_path):
    from floorscan.formats.image_io import read_grey

    port = free_port()
    cfg = Config.from_toml(
        f"""
[ranger]
threshold = 20.0
[outputs]
overlay = "none"
bag = false
[node]
transport = "zenoh"
odom_topic = ""
map_period_s = 0.1
zenoh_connect = ""
zenoh_listen = "tcp/127.0.0.1:{port}"
"""
    )
    lines = [ln.split() for ln in (room / "room" / "images.txt").read_text().split("\n")[1:] if ln]
    frames = [(float(t), read_grey(room / "room" / p)) for t, p in lines]
    node = NodeRun(
        GroundTable.load(room / "table.json"), cfg, tmp_path / "out"
    )  # runs until its source is closed below
    runner = threading.Thread(target=node.run)
    runner.start()
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{port}"]))
    robot = zenoh.open(conf)
    codec = Codec(2)
    scans, maps = [], []
    got = threading.Condition()

    def on(store):
        def cb(sample):
            with got:
                store.append(
                    (
                        sample.payload.to_bytes(),
                        sample.attachment.to_bytes() if sample.attachment else None,
                    )
                )
                got.notify_all()

        return cb

    # The keys a ROS 2 node computes for these topics (design document's format).
    scan_key = (
        f"0/scan/sensor_msgs::msg::dds_::LaserScan_/{codec.type_hash('sensor_msgs/msg/LaserScan')}"
    )
    map_key = (
        f"0/map/nav_msgs::msg::dds_::OccupancyGrid_/{codec.type_hash('nav_msgs/msg/OccupancyGrid')}"
    )
    image_key = f"0/camera/image_raw/sensor_msgs::msg::dds_::Image_/{codec.type_hash('sensor_msgs/msg/Image')}"
    subs = [
        robot.declare_subscriber(scan_key, on(scans)),
        robot.declare_subscriber(map_key, on(maps)),
    ]
    pub = robot.declare_publisher(image_key)
    try:
        # The graph: the node's liveliness tokens, as `ros2 node list` / `ros2 topic list` read them.
        deadline = time.monotonic() + 10
        tokens = set()
        while time.monotonic() < deadline and len(tokens) < 6:
            tokens = {str(r.ok.key_expr) for r in robot.liveliness().get("@ros2_lv/0/**") if r.ok}
            time.sleep(0.1)
        zid = node.transport.zid
        assert f"@ros2_lv/0/{zid}/0/0/NN/%/%/floorscan" in tokens
        scan_token = [t for t in tokens if "/MP/" in t and "%scan/" in t]
        assert scan_token == [
            f"@ros2_lv/0/{zid}/0/{scan_token[0].split('/')[4]}/MP/%/%/floorscan/%scan/"
            f"sensor_msgs::msg::dds_::LaserScan_/{codec.type_hash('sensor_msgs/msg/LaserScan')}/::,10:,:,:,,"
        ]
        assert any(
            "/MS/%/%/floorscan/%camera%image_raw/sensor_msgs::msg::dds_::Image_/" in t
            for t in tokens
        )
        assert any(t.endswith("/:1:,1:,:,:,,") and "%map/" in t for t in tokens)
        time.sleep(0.3)  # the node's subscriber reaches this session
        gid = bytes(16 * [7])
        for i, (t, grey) in enumerate(frames):
            pub.put(ros2_image(codec, t, grey), attachment=K.attachment(i + 1, time.time_ns(), gid))
            with got:
                got.wait_for(lambda n=i: len(scans) > n, timeout=5.0)
        # A late joiner asking for history (as rmw_zenoh's transient-local subscriptions do)
        # gets the latest map from the publisher's cache. Maps are only published after a
        # frame: past the last one (and a pause) nothing live is left to receive.
        from zenoh import ext

        time.sleep(0.5)
        late = []
        late_sub = ext.declare_advanced_subscriber(
            robot,
            map_key,
            lambda smp: late.append(smp.payload.to_bytes()),
            history=ext.HistoryConfig(detect_late_publishers=True),
        )
        deadline = time.monotonic() + 5
        while not late and time.monotonic() < deadline:
            time.sleep(0.05)
        late_sub.undeclare()
        assert late, "no map from the transient-local cache"
        node.source.close()
        runner.join(30)
        assert not runner.is_alive()
    finally:
        for s in subs:
            s.undeclare()
        robot.close()
        node.source.close()
        runner.join(10)
    assert len(scans) == len(frames)
    csv = tmp_path / "ref.csv"
    assert (
        main(
            [
                "scan",
                str(room / "room"),
                "--table",
                str(room / "table.json"),
                "-o",
                str(csv),
                "--threshold",
                "20",
            ]
        )
        == 0
    )
    ref = read_scans_csv(csv)
    seqs = []
    for (payload, att), scan in zip(scans, ref):
        assert payload[:4] == b"\x00\x01\x00\x00"  # CDR little-endian encapsulation
        laser = codec.deserialize(payload, "sensor_msgs/msg/LaserScan")
        assert codec.serialize(laser, "sensor_msgs/msg/LaserScan") == payload
        assert laser.header.frame_id == "camera_ground"
        want = scan.to_laser_scan(
            angle_min=laser.angle_min,
            angle_max=laser.angle_max,
            angle_increment=laser.angle_increment,
        )
        np.testing.assert_array_equal(laser.ranges, np.asarray(want["ranges"], np.float32))
        seq, ts_ns, pub_gid = K.parse_attachment(att)
        seqs.append(seq)
        assert abs(ts_ns - time.time_ns()) < 120e9 and len(pub_gid) == 16
        assert struct.unpack_from("<q", att)[0] == seq
    assert seqs == list(range(1, len(frames) + 1))
    # Maps arrive (without odometry only the local map grows).
    assert maps
    grid = codec.deserialize(maps[-1][0], "nav_msgs/msg/OccupancyGrid")
    assert grid.header.frame_id == "map" and grid.info.resolution == pytest.approx(0.04)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["node"]["scans_published"] == len(frames)
