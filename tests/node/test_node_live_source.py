"""The node's live inputs without any middleware: odometry interpolation and its timeout
against analytic poses, the one-slot image mailbox (newest wins, drops counted), the end of
iteration on a stop request, and the `[node]` option checks."""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest
from floorscan.errors import ImageError, OptionError
from floorscan.node.live_source import LiveOdometry, LiveSource
from floorscan.pipeline.config import Config
from floorscan.pipeline.config_check import check_config


def test_odometry_interpolates_holds_then_gives_up():
    odo = LiveOdometry(timeout_s=0.5)
    # A robot turning at 1 rad/s on a circle of radius 2 m, sampled at 10 Hz.
    for k in range(11):
        t = 10.0 + 0.1 * k
        a = t - 10.0
        odo.add(t, 2 * math.sin(a), 2 * (1 - math.cos(a)), a)
    p = odo.pose_at(10.55)  # between samples: linear in x, y and yaw
    a0, a1 = 0.5, 0.6
    assert p.yaw == pytest.approx(0.55)
    assert p.x == pytest.approx((2 * math.sin(a0) + 2 * math.sin(a1)) / 2)
    assert odo.pose_at(9.0) is None  # before the first pose: never extrapolated
    held = odo.pose_at(11.3)  # 0.3 s past the last pose, within the timeout: the last pose
    assert (held.x, held.yaw) == pytest.approx((2 * math.sin(1.0), 1.0))
    assert odo.pose_at(11.6) is None and odo.stale  # 0.6 s past: odometry stopped
    odo.add(11.7, 0.0, 0.0, 0.0)
    assert odo.pose_at(11.7) is not None and not odo.stale


def test_odometry_wraps_yaw_and_rejects_bad_samples():
    odo = LiveOdometry(timeout_s=1.0)
    odo.add(1.0, 0.0, 0.0, math.pi - 0.1)
    odo.add(2.0, 0.0, 0.0, -math.pi + 0.1)  # across +-pi: the short way round
    assert abs(odo.pose_at(1.5).yaw) == pytest.approx(math.pi)
    odo.add(1.5, 0.0, 0.0, 0.0)  # out of order
    odo.add(3.0, float("nan"), 0.0, 0.0)  # not finite
    assert (odo.received, odo.rejected) == (2, 2)


def _decode(data: bytes):
    if data == b"bad":
        raise ImageError("unsupported image encoding 'yuv422'")
    return float(data[0]), np.full((4, 6), data[0], np.uint8)


def test_newest_frame_wins_and_drops_are_counted():
    src = LiveSource(_decode, odometry=None, max_frames=2)
    for v in (1, 2, 3):
        src.push(bytes([v]), 0.0)
    frames = []

    def later():
        src.push(b"bad", 0.0)

    it = iter(src)
    frames.append(next(it))
    threading.Timer(0.1, later).start()
    frames.append(next(it))
    assert [f.timestamp for f in frames[:1]] == [3.0]
    assert frames[1].image is None and "yuv422" in frames[1].error
    assert (src.received, src.dropped) == (4, 2)
    assert next(it, None) is None  # max_frames


def test_a_stop_request_ends_the_wait_for_frames():
    class Stop:
        requested = False

    stop = Stop()
    src = LiveSource(_decode, odometry=None)
    src.bind_stop(stop)
    threading.Timer(0.1, lambda: setattr(stop, "requested", True)).start()
    assert list(src) == []


@pytest.mark.parametrize(
    "key, value, says",
    [
        ("transport", '"dds"', "node.transport"),
        ("scan_topic", '"/bad topic"', "node.scan_topic"),
        ("map_frame", '""', "node.map_frame"),
        ("map_period_s", "0.0", "node.map_period_s"),
        ("odom_timeout_s", "-1.0", "node.odom_timeout_s"),
        ("domain_id", "233", "node.domain_id"),
        ("foxglove_port", "70000", "node.foxglove_port"),
    ],
)
def test_node_options_are_checked(key, value, says):
    cfg = Config.from_toml(f"[node]\n{key} = {value}\n")
    with pytest.raises(OptionError, match=says.replace(".", r"\.")):
        check_config(cfg)


def test_default_node_options_pass_and_have_ros_names():
    n = check_config(Config()).node
    assert (n.image_topic, n.odom_topic, n.scan_topic, n.map_topic, n.local_map_topic) == (
        "/camera/image_raw",
        "/odom",
        "/scan",
        "/map",
        "/local_map",
    )
