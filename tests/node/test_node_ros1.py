"""`floorscan node` on a real ROS 1 master (roscore): frames of the synthetic room published
with rospy's own sensor_msgs / nav_msgs classes; the node's LaserScans must equal `floorscan
scan`'s on the same frames (same table, same options), its /map must agree with the room, and
it must survive bad input and a master that disappears, saving the map when stopped."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from floorscan import read_scans_csv
from floorscan.cli import main
from ros1_fixtures import Roscore, free_port, require_ros1
from synthetic_dataset import camera_table, make_dataset, true_occupied

# rospy and rosgraph leave XML-RPC sockets to the garbage collector.
pytestmark = [
    pytest.mark.filterwarnings("ignore::ResourceWarning"),
    pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning"),
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
]

N = 20
CONFIG = """
[ranger]
threshold = 20.0
[outputs]
overlay = "none"
bag = false
[node]
transport = "ros1"
map_period_s = 0.2
odom_timeout_s = 0.3
"""


@pytest.fixture(scope="module")
def ros(tmp_path_factory):
    rospy = require_ros1()
    core = Roscore(tmp_path_factory.mktemp("roscore"))
    os.environ["ROS_MASTER_URI"] = core.uri
    rospy.init_node("floorscan_test", anonymous=True, disable_signals=True)
    yield rospy, core
    rospy.signal_shutdown("tests done")
    core.stop()


@pytest.fixture(scope="module")
def room(tmp_path_factory):
    d = tmp_path_factory.mktemp("node_ds")
    make_dataset(d / "room", n=N)
    camera_table().save(d / "table.json")
    (d / "config.toml").write_text(CONFIG)
    return d


def start_node(room, out, env, *extra):
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            "floorscan",
            "node",
            "--table",
            str(room / "table.json"),
            "--config",
            str(room / "config.toml"),
            "-o",
            str(out),
            *extra,
        ],
        env=env,
        stderr=subprocess.PIPE,
        text=True,
    )


class Collector:
    def __init__(self, rospy, topic, cls):
        self.msgs = []
        self.event = threading.Condition()
        self.sub = rospy.Subscriber(topic, cls, self._on)

    def _on(self, msg):
        with self.event:
            self.msgs.append(msg)
            self.event.notify_all()

    def wait_for(self, n, timeout=5.0):
        deadline = time.monotonic() + timeout
        with self.event:
            while len(self.msgs) < n and time.monotonic() < deadline:
                self.event.wait(0.05)
        return len(self.msgs) >= n


def wait_connected(items, timeout=20.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if all(x.get_num_connections() > 0 for x in items):
            return True
        time.sleep(0.05)
    return False


def image_msg(rospy, t, grey, encoding="mono8"):
    from sensor_msgs.msg import Image

    m = Image()
    m.header.stamp = rospy.Time.from_sec(t)
    m.header.frame_id = "camera"
    m.height, m.width = grey.shape
    m.encoding = encoding
    m.step = grey.shape[1]
    m.data = grey.tobytes()
    return m


def odom_msg(rospy, t, x, y, yaw):
    from nav_msgs.msg import Odometry

    m = Odometry()
    m.header.stamp = rospy.Time.from_sec(t)
    m.header.frame_id = "odom"
    m.child_frame_id = "base_link"
    m.pose.pose.position.x, m.pose.pose.position.y = x, y
    m.pose.pose.orientation.z, m.pose.pose.orientation.w = np.sin(yaw / 2), np.cos(yaw / 2)
    return m


def stop_node(proc):
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err


def test_scans_equal_floorscan_scan_and_the_map_matches_the_room(ros, room, tmp_path):
    rospy, core = ros
    from floorscan.formats.image_io import read_grey
    from floorscan.formats.trajectory import read_tum
    from nav_msgs.msg import OccupancyGrid, Odometry
    from sensor_msgs.msg import Image, LaserScan
    from tf2_msgs.msg import TFMessage

    node = start_node(room, tmp_path / "out", core.env)
    img_pub = rospy.Publisher("/camera/image_raw", Image, queue_size=10)
    odo_pub = rospy.Publisher("/odom", Odometry, queue_size=100)
    scans = Collector(rospy, "/scan", LaserScan)
    maps = Collector(rospy, "/map", OccupancyGrid)
    tf = Collector(rospy, "/tf_static", TFMessage)
    try:
        assert wait_connected([img_pub, odo_pub, scans.sub, maps.sub]), "node never connected"
        odo = read_tum(room / "room" / "odometry.txt")
        lines = (room / "room" / "images.txt").read_text().split("\n")[1:]
        frames = [(float(a), room / "room" / b) for a, b in (ln.split() for ln in lines if ln)]
        sent = 0
        for t, x, y, yaw in zip(odo.timestamps, odo.x, odo.y, odo.yaw):
            odo_pub.publish(odom_msg(rospy, float(t), float(x), float(y), float(yaw)))
            time.sleep(0.02)  # the pose reaches the node before the frame it belongs to
            while sent < len(frames) and frames[sent][0] <= t:
                img_pub.publish(image_msg(rospy, frames[sent][0], read_grey(frames[sent][1])))
                sent += 1
                scans.wait_for(sent, timeout=5.0)
        assert scans.wait_for(N), f"{len(scans.msgs)} of {N} scans arrived"
        assert maps.wait_for(1, timeout=5.0), "no /map"
        assert tf.wait_for(1)
    finally:
        rc, err = stop_node(node)
    assert rc == 130, err
    # Same frames through `floorscan scan` with the same table and ranger options.
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
    assert len(scans.msgs) == len(ref) == N
    for laser, scan in zip(scans.msgs, ref):
        assert laser.header.frame_id == "camera_ground"
        assert abs(laser.header.stamp.to_sec() - scan.timestamp) < 1e-6
        want = scan.to_laser_scan(
            angle_min=laser.angle_min,
            angle_max=laser.angle_max,
            angle_increment=laser.angle_increment,
        )
        np.testing.assert_array_equal(
            np.asarray(laser.ranges, np.float32), np.asarray(want["ranges"], np.float32)
        )
    # The static transform: base_link -> camera_ground (the rig at the origin here).
    t0 = tf.msgs[0].transforms[0]
    assert (t0.header.frame_id, t0.child_frame_id) == ("base_link", "camera_ground")
    # The last /map against the room: occupied (>= 65) vs the true walls on known cells.
    m = maps.msgs[-1]
    assert m.header.frame_id == "map"  # built from the corrected poses; map -> odom on /tf
    data = np.asarray(m.data, dtype=np.int8).reshape(m.info.height, m.info.width)
    cell = m.info.resolution
    ys, xs = np.mgrid[0 : m.info.height, 0 : m.info.width]
    cx = m.info.origin.position.x + (xs + 0.5) * cell
    cy = m.info.origin.position.y + (ys + 0.5) * cell
    known = data >= 0
    agree = (data >= 65) == true_occupied(cx, cy, cell)
    assert known.sum() > 500
    assert agree[known].mean() >= 0.95
    # Shutdown saved the run's outputs, with the node's figures in the summary.
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["counts"]["frames_mapped"] == N
    assert summary["node"]["scans_published"] == N
    assert summary["node"]["latency_ms"]["count"] == N
    assert (tmp_path / "out" / "map.yaml").is_file()
    assert len(read_scans_csv(tmp_path / "out" / "scans.csv")) == N


def test_bad_input_is_logged_and_skipped_and_the_node_keeps_going(ros, room, tmp_path):
    rospy, core = ros
    from floorscan.formats.image_io import read_grey
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import Image, LaserScan

    node = start_node(room, tmp_path / "out", core.env)
    img_pub = rospy.Publisher("/camera/image_raw", Image, queue_size=10)
    odo_pub = rospy.Publisher("/odom", Odometry, queue_size=100)
    scans = Collector(rospy, "/scan", LaserScan)
    good = read_grey(room / "room" / "images" / "000000.png")
    try:
        assert wait_connected([img_pub, odo_pub, scans.sub]), "node never connected"

        def frame(t, grey, encoding="mono8", odom=True):
            if odom:
                odo_pub.publish(odom_msg(rospy, t, 0.0, 0.0, 0.0))
                time.sleep(0.05)
            img_pub.publish(image_msg(rospy, t, grey, encoding))
            time.sleep(0.3)

        frame(100.0, good)  # answered
        frame(100.1, good, encoding="yuv422", odom=False)  # unknown encoding
        frame(100.2, good[::3, ::3].copy(), odom=False)  # not the table's size
        frame(100.3, good)  # answered: the node kept going
        frame(105.0, good, odom=False)  # odometry stopped 4.7 s before (timeout 0.3 s)
        frame(105.1, good)  # odometry resumed: answered
        assert scans.wait_for(3)
        time.sleep(0.3)
    finally:
        rc, err = stop_node(node)
    assert rc == 130, err
    assert len(scans.msgs) == 3
    assert "unsupported image encoding 'yuv422'" in err
    assert "frames of 64x48 are skipped: the ground table is for 192x144" in err
    assert "odometry stopped" in err and "odometry resumed" in err
    counts = json.loads((tmp_path / "out" / "summary.json").read_text())["counts"]
    assert counts["frames_in"] == 6 and counts["frames_mapped"] == 3
    assert counts["skipped_unreadable"] == 1
    assert counts["skipped_wrong_size"] == 1
    assert counts["skipped_no_odometry"] == 1
    assert (tmp_path / "out" / "map.yaml").is_file()


def test_a_master_that_disappears_is_logged_and_the_map_still_saved(ros, room, tmp_path):
    core = Roscore(tmp_path)  # a master of its own, killed under the running node
    node = start_node(room, tmp_path / "out", core.env)
    try:
        import rosgraph

        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            if "/floorscan" in [n for n in _node_names(rosgraph, core.uri)]:
                break
            time.sleep(0.1)
        else:
            pytest.fail("the node never registered")
        core.stop()
        time.sleep(2.5)
        assert node.poll() is None, "the node must keep running without its master"
    finally:
        core.stop()
        rc, err = stop_node(node)
    assert rc == 130, err
    assert "is not answering" in err
    assert (tmp_path / "out" / "map.yaml").is_file()
    assert (tmp_path / "out" / "summary.json").is_file()


def _node_names(rosgraph, uri):
    try:
        state = rosgraph.Master("/probe", master_uri=uri).getSystemState()
    except Exception:
        return []
    return {n for group in state for _, nodes in group for n in nodes}


def test_no_master_is_a_one_line_error(room, tmp_path):
    require_ros1()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{free_port()}")
    proc = start_node(room, tmp_path / "out", env)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1
    assert err.strip().splitlines() == [
        f"floorscan node: error: no ROS master at {env['ROS_MASTER_URI']} (start roscore, or set ROS_MASTER_URI)"
    ]
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
