"""The live view: `floorscan node` with a Foxglove WebSocket server, watched by a plain
WebSocket client speaking Foxglove's protocol (subscribe, binary message frames) that decodes
the protobuf messages with the schemas the server advertises. The node runs on an in-memory
transport (the Transport interface, no middleware): the image, scan and maps it shows must be
the frames sent and the scans / maps the node published."""

from __future__ import annotations

import base64
import json
import struct
import threading
import time

import numpy as np
import pytest
from floorscan import GroundTable, read_scans_csv
from floorscan.cli import main
from floorscan.formats.rosbag import ROSBAGS_MISSING
from floorscan.node import NodeRun
from floorscan.node.messages import Codec
from floorscan.pipeline.config import Config
from node_loopback import LoopbackTransport
from ros1_fixtures import free_port
from synthetic_dataset import camera_table, make_dataset

pytest.importorskip("foxglove", reason="foxglove-sdk is not installed (pip install foxglove-sdk)")
ws_client = pytest.importorskip("websockets.sync.client", reason="websockets is not installed")
pytest.importorskip("google.protobuf", reason="protobuf is not installed")
pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the node's messages


def decoder(channel):
    from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

    fds = descriptor_pb2.FileDescriptorSet.FromString(base64.b64decode(channel["schema"]))
    pool = descriptor_pool.DescriptorPool()
    for f in fds.file:
        pool.Add(f)
    return message_factory.GetMessageClass(pool.FindMessageTypeByName(channel["schemaName"]))


def test_foxglove_client_sees_the_frames_scans_and_maps(tmp_path):
    make_dataset(tmp_path / "room", n=8)
    camera_table().save(tmp_path / "table.json")
    port = free_port()
    cfg = Config.from_toml(
        f'[ranger]\nthreshold = 20.0\n[outputs]\noverlay = "none"\nbag = false\n'
        f'[node]\nodom_topic = ""\nmap_period_s = 0.05\nfoxglove_port = {port}\n'
        'overlay_topic = "/camera/overlay"\n'
    )
    lines = [
        ln.split() for ln in (tmp_path / "room" / "images.txt").read_text().split("\n")[1:] if ln
    ]
    from floorscan.formats.image_io import read_grey

    frames = [(float(t), read_grey(tmp_path / "room" / p)) for t, p in lines]
    transport = LoopbackTransport()
    node = NodeRun(
        GroundTable.load(tmp_path / "table.json"),
        cfg,
        tmp_path / "out",
        transport=transport,
        max_frames=len(frames),
    )
    received = {}
    with ws_client.connect(
        f"ws://127.0.0.1:{port}", subprotocols=["foxglove.sdk.v1", "foxglove.websocket.v1"]
    ) as ws:
        channels = {}
        deadline = time.monotonic() + 10
        while len(channels) < 6 and time.monotonic() < deadline:
            msg = ws.recv(timeout=5)
            if isinstance(msg, str) and json.loads(msg)["op"] == "advertise":
                for c in json.loads(msg)["channels"]:
                    channels[c["id"]] = c
        by_topic = {c["topic"]: c for c in channels.values()}
        assert {"/camera/image", "/camera/boundary", "/scan", "/map", "/local_map", "/tf"} <= set(
            by_topic
        )
        subs = [{"id": i, "channelId": c["id"]} for i, c in enumerate(channels.values())]
        ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))
        sub_topic = {s["id"]: channels[s["channelId"]]["topic"] for s in subs}
        decoders = {c["topic"]: decoder(c) for c in channels.values()}

        def receive():
            while True:
                try:
                    msg = ws.recv(timeout=10)
                except Exception:  # the server closes the connection when the node stops
                    return
                if isinstance(msg, bytes) and msg[0] == 0x01:
                    sid, _log_ns = struct.unpack_from("<IQ", msg, 1)
                    topic = sub_topic[sid]
                    received.setdefault(topic, []).append(decoders[topic].FromString(msg[13:]))

        receiver = threading.Thread(target=receive)
        receiver.start()
        time.sleep(0.3)
        runner = threading.Thread(target=node.run)
        runner.start()
        codec = Codec(2)
        T = codec.types
        for t, grey in frames:
            sec = int(t)
            msg = T["sensor_msgs/msg/Image"](
                header=T["std_msgs/msg/Header"](
                    stamp=T["builtin_interfaces/msg/Time"](
                        sec=sec, nanosec=int(round((t - sec) * 1e9))
                    ),
                    frame_id="camera",
                ),
                height=grey.shape[0],
                width=grey.shape[1],
                encoding="mono8",
                is_bigendian=0,
                step=grey.shape[1],
                data=grey.ravel(),
            )
            transport.callbacks["/camera/image_raw"](
                codec.serialize(msg, "sensor_msgs/msg/Image"), time.perf_counter()
            )
            time.sleep(0.1)
        runner.join(30)
        receiver.join(30)
        assert not runner.is_alive() and not receiver.is_alive()
    n = len(frames)
    assert len(received["/camera/image"]) == n
    for img, (_, grey) in zip(received["/camera/image"], frames):
        assert (img.width, img.height, img.encoding) == (grey.shape[1], grey.shape[0], "mono8")
        assert img.data == grey.tobytes()
    csv = tmp_path / "ref.csv"
    assert (
        main(
            [
                "scan",
                str(tmp_path / "room"),
                "--table",
                str(tmp_path / "table.json"),
                "-o",
                str(csv),
                "--threshold",
                "20",
            ]
        )
        == 0
    )
    ref = read_scans_csv(csv)
    assert len(received["/scan"]) == n
    for fx, scan, ann in zip(received["/scan"], ref, received["/camera/boundary"]):
        want = scan.to_laser_scan(
            angle_min=fx.start_angle, angle_max=fx.end_angle, angle_increment=0.01
        )
        np.testing.assert_array_equal(np.asarray(fx.ranges), np.asarray(want["ranges"]))
        assert fx.frame_id == "camera_ground"
        pts = ann.points[0].points
        assert len(pts) == int(np.count_nonzero(scan.status_codes == 0))
    # The overlay topic: each frame with its scan drawn, as `floorscan overlay` draws it.
    from floorscan.ranging.overlay import draw_scan_overlay

    overlays = [
        codec.deserialize(b, "sensor_msgs/msg/Image")
        for b in transport.published["/camera/overlay"]
    ]
    assert len(overlays) == n
    for o, (_, grey), scan in zip(overlays, frames, ref):
        assert (o.encoding, o.height, o.width, o.step) == (
            "rgb8",
            grey.shape[0],
            grey.shape[1],
            3 * grey.shape[1],
        )
        assert np.array_equal(
            np.asarray(o.data).reshape(o.height, o.width, 3), draw_scan_overlay(grey, scan)
        )
    # The last map shown is the last map published on the (loopback) ROS topic.
    grid = received["/local_map"][-1]
    ros = codec.deserialize(transport.published["/local_map"][-1], "nav_msgs/msg/OccupancyGrid")
    assert grid.column_count == ros.info.width
    assert np.array_equal(np.frombuffer(grid.data, np.int8), np.asarray(ros.data, np.int8))
    assert any(tf.transforms for tf in received["/tf"])
