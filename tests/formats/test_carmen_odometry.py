"""Raw odometry at each laser reading of a CARMEN log: raw logs as logged, corrected logs rebuilt
from their anchors. Synthetic logs built from a known dead-reckoned path and a known correction
give the path back; the shared corrected logs give motions near their corrected ones."""

import math

import numpy as np
import pytest
from conftest import shared_data_dir
from floorscan import DatasetError
from floorscan.formats.carmen import parse_carmen_lines, read_carmen
from floorscan.formats.carmen_odometry import log_odometry
from floorscan.formats.trajectory import compose


def inverse(p):
    c, s = math.cos(p[2]), math.sin(p[2])
    return (-c * p[0] - s * p[1], s * p[0] - c * p[1], -p[2])


def flaser(pose, odom, t):
    return (
        f"FLASER 4 1 1 1 1 {pose[0]!r} {pose[1]!r} {pose[2]!r} {odom[0]!r} {odom[1]!r} "
        f"{odom[2]!r} {t!r} host {t!r}"
    )


def odom(pose, t, tv=0.0, rv=0.0):
    return f"ODOM {pose[0]!r} {pose[1]!r} {pose[2]!r} {tv!r} {rv!r} 0 {t!r} host {t!r}"


def path(n, rng):
    """A dead-reckoned path with odometry samples between scans: (scan poses, per-scan list of
    the odometry poses sampled after it, up to the next scan)."""
    poses, between = [(0.5, -1.0, 0.2)], []
    for _ in range(n - 1):
        samples, p = [], poses[-1]
        for _ in range(int(rng.integers(1, 5))):
            p = compose(p, (rng.uniform(0, 0.1), rng.uniform(-0.01, 0.01), rng.uniform(-0.2, 0.2)))
            samples.append(p)
        between.append(samples)
        poses.append(p)
    return poses, between


@pytest.mark.parametrize("anchor_t", [0.0, 1.08499e-42, 1.13])
def test_a_corrected_log_gives_back_the_dead_reckoned_path(anchor_t):
    # an anchor's timestamp 0 is written as garbage in part of the Intel log
    rng = np.random.default_rng(3)
    raw, between = path(30, rng)
    # A SLAM run's corrected poses: the raw path bent by a slowly growing correction.
    corrected = [compose((0.02 * k, -0.01 * k, 0.005 * k), p) for k, p in enumerate(raw)]
    # The log starts where the corrected path starts.
    start = compose(corrected[0], inverse(raw[0]))
    lines, t = [], 100.0  # (a log's clock: the garbage 1.13 lies well before every scan)
    for k, c in enumerate(corrected):
        lines.append(flaser(c, c, t))
        lines.append(odom(c, anchor_t))  # the anchor
        if k < len(between):
            to_anchor = compose(c, inverse(raw[k]))  # raw frame moved to start at the anchor
            for p in between[k]:
                t += 0.1
                lines.append(odom(compose(to_anchor, p), t))
    o = log_odometry(parse_carmen_lines(lines))
    assert o.rebuilt and o.extrapolated == 0
    expected = np.array([compose(start, p) for p in raw])
    np.testing.assert_allclose(o.robot_poses, expected, atol=1e-9)
    np.testing.assert_allclose(o.laser_poses, expected, atol=1e-9)


def test_a_raw_log_gives_its_own_odometry_and_the_lasers_mount():
    rng = np.random.default_rng(5)
    raw, _ = path(10, rng)
    mount = (0.12, -0.03, 0.0)
    lines = [flaser(compose(p, mount), p, 0.1 * k) for k, p in enumerate(raw)]
    o = log_odometry(parse_carmen_lines(lines))
    assert not o.rebuilt
    np.testing.assert_allclose(o.robot_poses, np.array(raw), atol=1e-12)
    np.testing.assert_allclose(o.laser_poses, [compose(p, mount) for p in raw], atol=1e-9)


def test_scans_without_odometry_between_them_move_by_the_last_velocities():
    lines = [
        flaser((0, 0, 0), (0, 0, 0), 0.0),
        odom((0, 0, 0), 0.0),
        odom((0.1, 0, 0), 0.5, tv=0.2, rv=0.0),
        flaser((0.1, 0, 0), (0.1, 0, 0), 0.5),
        # no anchor, no odometry: 1 s at 0.2 m/s straight ahead
        flaser((9, 9, 0), (9, 9, 0), 1.5),
    ]
    o = log_odometry(parse_carmen_lines(lines))
    assert o.rebuilt and o.extrapolated == 1
    np.testing.assert_allclose(o.robot_poses[-1], (0.3, 0.0, 0.0), atol=1e-12)


def test_a_log_without_lasers_is_an_error():
    with pytest.raises(DatasetError, match="no laser lines"):
        log_odometry(parse_carmen_lines([odom((0, 0, 0), 1.0)]))


CARMEN = shared_data_dir() / "carmen"


@pytest.mark.skipif(not CARMEN.is_dir(), reason=f"real CARMEN logs not found at {CARMEN}")
@pytest.mark.parametrize("name", ["intel-corrected.log.gz", "freiburg-079-corrected.log.gz"])
def test_real_odometry_moves_about_as_the_corrected_poses_do(name):
    """Each scan-to-scan motion of the rebuilt odometry against the SLAM run's: odometry is off
    by centimetres and a few degrees a step, not by the whole motion, yet its path drifts."""
    log = read_carmen(CARMEN / name)
    o = log_odometry(log)
    truth = np.array([r.robot_pose for r in log.lasers])
    assert o.rebuilt and o.robot_poses.shape == truth.shape
    step_err, step = [], []
    for k in range(len(truth) - 1):
        m = compose(inverse(o.robot_poses[k]), o.robot_poses[k + 1])
        t = compose(inverse(truth[k]), truth[k + 1])
        step_err.append(
            (math.hypot(m[0] - t[0], m[1] - t[1]), abs(math.remainder(m[2] - t[2], 2 * math.pi)))
        )
        step.append((math.hypot(t[0], t[1]), abs(math.remainder(t[2], 2 * math.pi))))
    step_err, step = np.array(step_err), np.array(step)
    moving = step[:, 0] > 0.05
    assert np.median(step_err[moving, 0]) < 0.5 * np.median(step[moving, 0])
    assert np.median(step_err[:, 1]) < math.radians(3)
    # ... and the dead-reckoned path ends metres from the corrected one (why logs need SLAM).
    end = o.robot_poses[-1] - truth[-1]
    assert math.hypot(end[0], end[1]) > 1.0
