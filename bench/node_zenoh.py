"""`floorscan node` over ROS 2's Zenoh protocol (rmw_zenoh), at 640x480 and 10 Hz.

Two Zenoh sessions on localhost (peer to peer, no router): the node's, and a "robot" session
in the same process that publishes a simulated 640x480 corridor run as a ROS 2 node on
rmw_zenoh would (CDR sensor_msgs/Image mono8 + nav_msgs/Odometry, rmw_zenoh key expressions
and attachments) at 10 Hz, and subscribes to /scan. Counts the answered frames, compares them
with `floorscan scan` on the same frames and reports the latencies (in the node: image
received -> scan published, decode included; end to end: put -> scan received).

Run: .venv/bin/python bench/node_zenoh.py [--seconds 30]   (prints Markdown; needs eclipse-zenoh)
"""

from __future__ import annotations

import argparse
import json
import socket
import tempfile
import threading
import time
from pathlib import Path

import numpy as np


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=30.0)
    args = ap.parse_args()
    import zenoh
    from floorscan import read_scans_csv
    from floorscan.cli import main as cli
    from floorscan.formats.trajectory import quaternion_from_yaw
    from floorscan.node import NodeRun
    from floorscan.node import rmw_zenoh_keys as K
    from floorscan.node.messages import Codec
    from floorscan.pipeline.config import Config
    from floorscan.sim import Camera, World, simulate_run

    tmp = Path(tempfile.mkdtemp(prefix="floorscan-zenoh-bench-"))
    cam = Camera(width=640, height=480)
    sim = simulate_run(
        World.builtin("corridor"),
        camera=cam,
        seconds=args.seconds,
        seed=3,
        threads=2,
        labels=False,
        truth=False,
    )
    n = len(sim)
    table = cam.ground_table(spacing_px=8)
    table.save(tmp / "table.json")
    port = free_port()
    cfg = Config.from_toml(
        f'[outputs]\noverlay = "none"\nbag = false\n[node]\ntransport = "zenoh"\n'
        f'zenoh_connect = ""\nzenoh_listen = "tcp/127.0.0.1:{port}"\n'
    )
    node = NodeRun(table, cfg, tmp / "out", robot_from_camera=cam.robot_from_camera, max_frames=n)
    runner = threading.Thread(target=node.run)
    runner.start()
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{port}"]))
    robot = zenoh.open(conf)
    codec = Codec(2)
    T = codec.types
    key = lambda topic, typ: K.topic_keyexpr(0, topic, typ, codec.type_hash(typ))  # noqa: E731
    got = {}

    def on_scan(sample):
        laser = codec.deserialize(sample.payload.to_bytes(), "sensor_msgs/msg/LaserScan")
        t = round(laser.header.stamp.sec + laser.header.stamp.nanosec * 1e-9, 6)
        got[t] = (laser, time.perf_counter())

    sub = robot.declare_subscriber(key("/scan", "sensor_msgs/msg/LaserScan"), on_scan)
    img_pub = robot.declare_publisher(key("/camera/image_raw", "sensor_msgs/msg/Image"))
    odo_pub = robot.declare_publisher(key("/odom", "nav_msgs/msg/Odometry"))
    gid = bytes(16)
    time.sleep(1.0)

    def header(t, frame):
        sec = int(t)
        stamp = T["builtin_interfaces/msg/Time"](sec=sec, nanosec=int(round((t - sec) * 1e9)))
        return T["std_msgs/msg/Header"](stamp=stamp, frame_id=frame)

    zero3 = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
    sent_at = {}
    start = time.perf_counter()
    for k in range(n):
        t = float(sim.timestamps[k])
        x, y, yaw = (float(v) for v in sim.odometry[k])
        qx, qy, qz, qw = quaternion_from_yaw(yaw)
        odom = T["nav_msgs/msg/Odometry"](
            header=header(t, "odom"),
            child_frame_id="base_link",
            pose=T["geometry_msgs/msg/PoseWithCovariance"](
                pose=T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=x, y=y, z=0.0),
                    orientation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
                ),
                covariance=np.zeros(36),
            ),
            twist=T["geometry_msgs/msg/TwistWithCovariance"](
                twist=T["geometry_msgs/msg/Twist"](linear=zero3, angular=zero3),
                covariance=np.zeros(36),
            ),
        )
        odo_pub.put(
            codec.serialize(odom, "nav_msgs/msg/Odometry"),
            attachment=K.attachment(k + 1, time.time_ns(), gid),
        )
        grey = np.ascontiguousarray(sim.images[k], dtype=np.uint8)
        img = T["sensor_msgs/msg/Image"](
            header=header(t, "camera"),
            height=grey.shape[0],
            width=grey.shape[1],
            encoding="mono8",
            is_bigendian=0,
            step=grey.shape[1],
            data=grey.ravel(),
        )
        payload = codec.serialize(img, "sensor_msgs/msg/Image")
        sent_at[round(t, 6)] = time.perf_counter()
        img_pub.put(payload, attachment=K.attachment(k + 1, time.time_ns(), gid))
        time.sleep(max(0.0, start + (k + 1) * 0.1 - time.perf_counter()))
    runner.join(30)
    time.sleep(0.5)
    sub.undeclare()
    robot.close()
    summary = json.loads((tmp / "out" / "summary.json").read_text())
    ds = sim.write_dataset(tmp / "ds", calibration=None, truth=False, labels=False)
    cli(["scan", str(ds), "--table", str(tmp / "table.json"), "-o", str(tmp / "ref.csv")])
    ref = {round(s.timestamp, 6): s for s in read_scans_csv(tmp / "ref.csv")}
    equal = 0
    for t, (laser, _) in got.items():
        want = ref[t].to_laser_scan(
            angle_min=laser.angle_min,
            angle_max=laser.angle_max,
            angle_increment=laser.angle_increment,
        )
        equal += np.array_equal(laser.ranges, np.asarray(want["ranges"], np.float32))
    lat = np.asarray([1e3 * (got[t][1] - sent_at[t]) for t in sent_at if t in got])
    nl = summary["node"]["latency_ms"]
    print(
        f"640x480 corridor, {n} frames at 10 Hz through two Zenoh sessions (rmw_zenoh protocol)\n"
    )
    print("| figure | value |")
    print("|---|---:|")
    print(
        f"| frames answered on /scan | {len(got)}/{len(sent_at)} = {100 * len(got) / len(sent_at):.1f} % |"
    )
    print(
        f"| scans equal to `floorscan scan`'s (float32 ranges, bit for bit) | {equal}/{len(got)} |"
    )
    print(f"| frames mapped (odometry matched) | {summary['counts']['frames_mapped']} |")
    print(f"| dropped by the node | {summary['node']['dropped_frames']} |")
    print(
        f"| in-node latency, decode included: p50 / p99 / max | {nl['p50']:.2f} / {nl['p99']:.2f} / {nl['max']:.2f} ms |"
    )
    print(
        f"| end to end (put -> scan received): p50 / p99 | {np.percentile(lat, 50):.2f} / {np.percentile(lat, 99):.2f} ms |"
    )


if __name__ == "__main__":
    main()
