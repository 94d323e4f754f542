"""`floorscan node` live on a real ROS 1 master (roscore), at 640x480 and 10 Hz.

A simulated 640x480 corridor run (python/floorscan/sim) is published with rospy as
sensor_msgs/Image (mono8) + nav_msgs/Odometry at 10 Hz to a `floorscan node` process; the /scan
messages that come back are counted and compared with `floorscan scan` on the same frames (same
ground table, same ranger options). Latency:
- in the node: image received (rospy callback) -> LaserScan published, decode included (the
  node's own measurement, summary.json);
- end to end: image published here -> LaserScan received here (two rospy hops included),
  against the baseline a rospy user would write first: a relay node on Debian's python3 that
  answers each Image with an empty LaserScan (the middleware's own cost, no processing).

Run: .venv/bin/python bench/node_ros1.py [--seconds 30]   (prints Markdown; needs roscore + rospy)
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

RELAY = r"""
import rospy
from sensor_msgs.msg import Image, LaserScan
rospy.init_node("relay")
pub = rospy.Publisher("/scan", LaserScan, queue_size=10)
def on_image(img):
    s = LaserScan()
    s.header = img.header
    pub.publish(s)
rospy.Subscriber("/camera/image_raw", Image, on_image, queue_size=1, buff_size=1 << 24)
rospy.spin()
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_roscore(tmp: Path):
    import rosgraph

    port = free_port()
    uri = f"http://127.0.0.1:{port}"
    env = dict(os.environ, ROS_MASTER_URI=uri, ROS_HOME=str(tmp / "ros_home"))
    proc = subprocess.Popen(
        ["roscore", "-p", str(port)],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    while not rosgraph.is_master_online(uri):
        time.sleep(0.1)
    return proc, env


def publish_run(rospy, sim, n, *, wait_s=20.0):
    """Publishes n frames at 10 Hz; returns (frames sent, scans by stamp, end-to-end latencies)."""
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import Image, LaserScan

    img_pub = rospy.Publisher("/camera/image_raw", Image, queue_size=1)
    odo_pub = rospy.Publisher("/odom", Odometry, queue_size=10)
    sent_at = {}
    got = {}

    def on_scan(s):
        t = round(s.header.stamp.to_sec(), 6)
        got[t] = (s, time.perf_counter())

    sub = rospy.Subscriber("/scan", LaserScan, on_scan, queue_size=100)
    deadline = time.monotonic() + wait_s
    while img_pub.get_num_connections() == 0 or sub.get_num_connections() == 0:
        if time.monotonic() > deadline:
            raise SystemExit("the node never connected")
        time.sleep(0.05)
    time.sleep(0.5)
    start = time.perf_counter()
    for k in range(n):
        t = float(sim.timestamps[k])
        x, y, yaw = (float(v) for v in sim.odometry[k])
        o = Odometry()
        o.header.stamp = rospy.Time.from_sec(t)
        o.header.frame_id, o.child_frame_id = "odom", "base_link"
        o.pose.pose.position.x, o.pose.pose.position.y = x, y
        o.pose.pose.orientation.z, o.pose.pose.orientation.w = np.sin(yaw / 2), np.cos(yaw / 2)
        odo_pub.publish(o)
        grey = np.ascontiguousarray(sim.images[k], dtype=np.uint8)
        m = Image()
        m.header.stamp = rospy.Time.from_sec(t)
        m.header.frame_id = "camera"
        m.height, m.width = grey.shape
        m.encoding, m.step, m.data = "mono8", grey.shape[1], grey.tobytes()
        sent_at[round(t, 6)] = time.perf_counter()
        img_pub.publish(m)
        next_tick = start + (k + 1) * 0.1
        time.sleep(max(0.0, next_tick - time.perf_counter()))
    time.sleep(1.0)
    sub.unregister()
    img_pub.unregister()
    odo_pub.unregister()
    lat = [1e3 * (got[t][1] - sent_at[t]) for t in sent_at if t in got]
    return sent_at, got, np.asarray(lat)


def stop(proc) -> str:
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    return err


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=30.0)
    args = ap.parse_args()
    from floorscan.node.ros1 import import_rospy
    from floorscan.sim import Camera, World, simulate_run

    rospy = import_rospy()
    tmp = Path(tempfile.mkdtemp(prefix="floorscan-node-bench-"))
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
    cam.ground_table(spacing_px=8).save(tmp / "table.json")
    rx, ry, ryaw = cam.robot_from_camera
    (tmp / "node.toml").write_text(
        f'[rig]\nx = {rx}\ny = {ry}\nyaw = {ryaw}\n[outputs]\noverlay = "none"\nbag = false\n'
    )
    core, env = start_roscore(tmp)
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    rospy.init_node("floorscan_bench", disable_signals=True)
    try:
        node = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "floorscan",
                "node",
                "--table",
                str(tmp / "table.json"),
                "--config",
                str(tmp / "node.toml"),
                "-o",
                str(tmp / "out"),
            ],
            env=env,
            stderr=subprocess.PIPE,
            text=True,
        )
        sent, got, lat = publish_run(rospy, sim, n)
        stop(node)
        relay = subprocess.Popen(
            ["/usr/bin/python3", "-c", RELAY], env=env, stderr=subprocess.PIPE, text=True
        )
        _, _, lat_relay = publish_run(rospy, sim, n)
        stop(relay)
    finally:
        rospy.signal_shutdown("bench done")
        os.killpg(core.pid, signal.SIGINT)
        core.wait(10)
    summary = json.loads((tmp / "out" / "summary.json").read_text())
    node_lat = summary["node"]["latency_ms"]
    # The same frames through `floorscan scan` (same table, default ranger options = the node's).
    from floorscan import read_scans_csv
    from floorscan.cli import main as cli

    ds = sim.write_dataset(tmp / "ds", calibration=None, truth=False, labels=False)
    cli(["scan", str(ds), "--table", str(tmp / "table.json"), "-o", str(tmp / "ref.csv")])
    ref = {round(s.timestamp, 6): s for s in read_scans_csv(tmp / "ref.csv")}
    equal = 0
    for t, (laser, _) in got.items():
        s = ref[t]
        want = s.to_laser_scan(
            angle_min=laser.angle_min,
            angle_max=laser.angle_max,
            angle_increment=laser.angle_increment,
        )
        equal += np.array_equal(
            np.asarray(laser.ranges, np.float32), np.asarray(want["ranges"], np.float32)
        )
    answered = len(got) / len(sent)
    p = lambda a, q: float(np.percentile(a, q))  # noqa: E731
    print(f"640x480 corridor, {n} frames published at 10 Hz to `floorscan node` over roscore\n")
    print("| figure | value |")
    print("|---|---:|")
    print(f"| frames answered on /scan | {len(got)}/{len(sent)} = {100 * answered:.1f} % |")
    print(
        f"| scans equal to `floorscan scan`'s (float32 ranges, bit for bit) | {equal}/{len(got)} |"
    )
    print(
        f"| dropped by the node (newer frame arrived first) | {summary['node']['dropped_frames']} |"
    )
    print(
        f"| in-node latency, image received -> scan published, decode included: p50 / p99 / max | "
        f"{node_lat['p50']:.2f} / {node_lat['p99']:.2f} / {node_lat['max']:.2f} ms |"
    )
    print(
        f"| end to end (publish here -> scan received here): p50 / p99 | "
        f"{p(lat, 50):.2f} / {p(lat, 99):.2f} ms |"
    )
    print(
        f"| baseline: rospy relay answering each Image with an empty LaserScan: p50 / p99 | "
        f"{p(lat_relay, 50):.2f} / {p(lat_relay, 99):.2f} ms |"
    )
    print(f"| end-to-end p50 ratio floorscan node / relay | {p(lat, 50) / p(lat_relay, 50):.2f} |")


if __name__ == "__main__":
    main()
