"""The scan matcher against geometry it must recover: a scan of a room stored at a known pose
is found again from a perturbed odometry pose; a lone straight wall fixes only what it can."""

from __future__ import annotations

import math

import numpy as np
import pytest
from floorscan.errors import OptionError
from floorscan.mapping.scan_matcher import MatchResult, ScanMatcher, ScanMatcherOptions


def _room_scan(pose, n=180):
    """Points (N, 2) [robot frame] where rays from ``pose`` over 270 degrees meet the walls
    of a 4 x 3 m room with corners (0, 0) and (4, 3) and a 0.4 m box at (2.5, 2.0)."""
    segs = [
        ((0, 0), (4, 0)),
        ((4, 0), (4, 3)),
        ((4, 3), (0, 3)),
        ((0, 3), (0, 0)),
        ((2.3, 1.8), (2.7, 1.8)),
        ((2.7, 1.8), (2.7, 2.2)),
        ((2.7, 2.2), (2.3, 2.2)),
        ((2.3, 2.2), (2.3, 1.8)),
    ]
    x, y, th = pose
    out = []
    for a in np.linspace(-3 * math.pi / 4, 3 * math.pi / 4, n):
        dx, dy = math.cos(th + a), math.sin(th + a)
        best = math.inf
        for (ax, ay), (bx, by) in segs:
            ex, ey = bx - ax, by - ay
            den = dx * ey - dy * ex
            if abs(den) < 1e-12:
                continue
            t = ((ax - x) * ey - (ay - y) * ex) / den
            s = ((ax - x) * dy - (ay - y) * dx) / den
            if t > 0 and 0 <= s <= 1:
                best = min(best, t)
        if best <= 3.0:
            out.append((best * math.cos(a), best * math.sin(a)))
    return np.array(out)


def test_a_scan_is_found_again_from_a_perturbed_odometry_pose():
    truth = (1.5, 1.2, 0.3)
    m = ScanMatcher(center=(2, 1.5))
    m.insert(_room_scan(truth), truth)
    later = (1.7, 1.1, 0.45)  # the robot moved; odometry is off by 9 cm and 0.05 rad
    odometry = (later[0] + 0.06, later[1] - 0.07, later[2] + 0.05)
    r = m.match(_room_scan(later), odometry)
    assert r.accepted
    cell = m.options.cell_size_m
    assert math.hypot(r.pose[0] - later[0], r.pose[1] - later[1]) <= 1.5 * cell
    assert abs(r.pose[2] - later[2]) <= 1.5 * m.options.yaw_step_rad


def test_a_lone_wall_fixes_the_distance_to_it_not_the_position_along_it():
    wall = np.stack([np.linspace(-2, 2, 81), np.full(81, 1.0)], 1)  # y = 1 m, robot frame
    m = ScanMatcher()
    m.insert(wall, (0.0, 0.0, 0.0))
    r = m.match(wall, (0.1, -0.08, 0.0))  # prior 10 cm along the wall, 8 cm towards it
    assert r.accepted
    assert abs(r.pose[1] - 0.0) <= m.options.cell_size_m  # across the wall: corrected
    # along it: odometry kept, up to the ripple of a field made of hits 5 cm apart
    assert abs(r.pose[0] - 0.1) <= 2 * m.options.cell_size_m


def test_an_empty_map_or_too_few_points_keeps_odometry():
    m = ScanMatcher()
    prior = (0.3, -0.2, 0.1)
    assert m.match(np.ones((40, 2)), prior) == m.match(np.ones((40, 2)), prior)
    assert not m.match(np.ones((40, 2)), prior).accepted
    m.insert(np.ones((40, 2)), (0, 0, 0))
    r = m.match(np.ones((3, 2)), prior)
    assert not r.accepted and r.pose == prior


def test_a_scan_unlike_the_map_is_refused():
    m = ScanMatcher()
    m.insert(_room_scan((1.5, 1.2, 0.3)), (1.5, 1.2, 0.3))
    rng = np.random.default_rng(0)
    r = m.match(rng.uniform(-3, 3, (100, 2)), (1.5, 1.2, 0.3))
    assert not r.accepted


@pytest.mark.parametrize(
    "kwargs", [{"size_m": 1.0}, {"cell_size_m": 0.0}, {"min_score": 1.5}, {"min_points": 1}]
)
def test_options_are_validated(kwargs):
    with pytest.raises(OptionError):
        ScanMatcherOptions(**kwargs)


def test_only_points_the_map_does_not_explain_are_stored():
    m = ScanMatcher()
    wall = np.stack([np.linspace(-1, 1, 41), np.full(41, 1.0)], 1)
    assert m.insert(wall, (0.0, 0.0, 0.0)) > 0
    before = m.hits.copy()
    # the same wall seen 3 cm off (within novelty_m) adds nothing; a new wall 1 m away is kept
    assert m.insert(wall, (0.0, 0.03, 0.0), novel_only=True) == 0
    assert np.array_equal(m.hits, before)
    other = np.stack([np.full(21, 2.0), np.linspace(-0.5, 0.5, 21)], 1)
    assert m.insert(other, (0.0, 0.0, 0.0), novel_only=True) == 21


def test_a_drifted_return_is_pulled_back_to_the_first_view():
    """Frames seen from a pose whose heading drifts by 0.01 rad per frame: matched against a
    map that keeps the first view, the heading error does not grow."""
    m = ScanMatcher(center=(2, 1.5))
    truth = (1.5, 1.2, 0.3)
    m.correct(_room_scan(truth), truth)
    estimate = truth
    errors = []
    for _ in range(12):
        # odometry says the robot turned 0.01 rad more than it did, each frame
        estimate = (estimate[0], estimate[1], estimate[2] + 0.01)
        estimate = m.correct(_room_scan(truth), estimate).pose
        errors.append(abs(estimate[2] - truth[2]))
    # fused with odometry, the estimate lags by about a frame's false turn, no more
    assert max(errors[6:]) <= 2 * m.options.yaw_step_rad
    assert errors[-1] <= errors[5] + 0.002


def test_the_cached_field_with_new_hits_stamped_equals_a_fresh_field():
    m = ScanMatcher(center=(2, 1.5))
    m.insert(_room_scan((1.5, 1.2, 0.3)), (1.5, 1.2, 0.3))
    cached, i0, j0 = m.cover(1.5, 1.2, 3.3)
    m.insert(_room_scan((2.5, 1.0, 2.0)), (2.6, 1.1, 2.05))  # a shifted copy: new hits
    fresh, f0, g0 = m.field_around(1.5, 1.2, 3.3 + 1.0)
    assert (i0, j0) == (f0, g0) and m.field[1:] == (i0, j0)
    assert np.array_equal(m.field[0], fresh) and not np.array_equal(cached, fresh)


def test_refinement_recovers_a_shift_smaller_than_a_cell():
    """Hits are stored by cell, so a wall is known to within its cell: with the grid placed so
    that the room's walls run through cell centres, the refined pose is the true one."""
    truth = (1.5, 1.2, 0.3)
    m = ScanMatcher(center=(2 + 0.0125, 1.5 + 0.0125))
    m.insert(_room_scan(truth, n=540), truth)
    # 1 cm and 0.004 rad off: below the search's cell (2.5 cm) and yaw step (0.01 rad)
    r = m.match(_room_scan(truth, n=540), (truth[0] + 0.01, truth[1] - 0.008, truth[2] + 0.004))
    assert r.accepted
    assert math.hypot(r.pose[0] - truth[0], r.pose[1] - truth[1]) < 0.006
    assert abs(r.pose[2] - truth[2]) < 0.003


LEGS = [(0.0, 1.0), (0.2, 0.0), (0.0, -1.2), (0.15, 0.3), (0.0, 1.5), (-0.15, 0.0)]


def _calibration_run(noise, legs, seconds_per_leg=2.0):
    """Drives the 4 x 3 room with the simulator's kinematics and the given odometry errors
    (``legs``: (v [m/s], omega [rad/s]) for ``seconds_per_leg`` each), corrects odometry with the matcher scan by scan;
    returns the matcher, the true poses and the estimates."""
    from floorscan.sim import Robot

    robot = Robot(frame_rate_hz=10, odometry=noise)
    commands = [[seconds_per_leg, v, w] for v, w in legs]
    tr = robot.drive(start=(2.0, 1.5, 0.0), seconds=len(legs) * seconds_per_leg, commands=commands)
    m = ScanMatcher(center=(2.0, 1.5))
    est = tuple(tr.poses[0])
    estimates = []
    for k in range(len(tr.poses)):
        if k > 0:
            a, b = tr.odometry[k - 1], tr.odometry[k]
            c, s = math.cos(a[2]), math.sin(a[2])
            dx, dy = b[0] - a[0], b[1] - a[1]
            inc = (c * dx + s * dy, -s * dx + c * dy, b[2] - a[2])
            c, s = math.cos(est[2]), math.sin(est[2])
            est = (
                est[0] + c * inc[0] - s * inc[1],
                est[1] + s * inc[0] + c * inc[1],
                est[2] + inc[2],
            )
        est = m.correct(_room_scan(tuple(tr.poses[k])), est).pose
        estimates.append(est)
    return m, np.asarray(tr.poses), np.asarray(tr.odometry), np.asarray(estimates)


def _no_noise(**kw):
    from floorscan.sim.robot import OdometryNoise

    base = dict(
        wheel_sigma_per_sqrt_m=0.0,
        radius_scale_error=0.0,
        radius_difference=0.0,
        wheelbase_error=0.0,
    )
    return OdometryNoise(**{**base, **kw})


def test_a_wheelbase_error_is_estimated_from_the_matches():
    """Odometry whose wheelbase is 5 % off reads every turn 1 / 1.05 of its angle: the turn
    scale the matcher estimates converges to the ratio of true to odometry turning measured on
    the trajectory itself."""
    m, poses, odo, _ = _calibration_run(_no_noise(wheelbase_error=0.05), LEGS * 3)
    true_turn = np.abs(np.diff(np.unwrap(poses[:, 2]))).sum()
    odo_turn = np.abs(np.diff(np.unwrap(odo[:, 2]))).sum()
    expected = true_turn / odo_turn - 1.0  # 0.05
    assert abs(expected - 0.05) < 1e-3
    assert abs(m.calibration[0] - expected) < 0.01


def test_a_wheel_radius_difference_is_estimated_as_heading_drift_per_metre():
    """Wheels 0.6 % different in radius: straight driving reads as a curve of 0.006 / wheelbase
    = 0.02 rad per metre (the regression of the true heading's increments on odometry's over
    the trajectory gives the same); from 0, the estimate gets its sign and comes within
    0.015 rad/m (half its prior's width) over 7.6 m of driving, and the heading stays within
    a yaw step of the truth while odometry's ends 0.15 rad off."""
    m, poses, odo, est = _calibration_run(
        _no_noise(radius_difference=0.006),
        [(0.15, 0.0), (0.0, 1.0), (0.15, 0.0), (0.0, -1.0)] * 8,
        seconds_per_leg=math.pi,
    )
    expected = -0.006 / 0.3
    turn = np.diff(np.unwrap(poses[:, 2])) - np.diff(np.unwrap(odo[:, 2]))
    dist = np.hypot(*np.diff(odo[:, :2], axis=0).T)
    assert abs(np.sum(turn * dist) / np.sum(dist * dist) - expected) < 1e-4
    assert m.calibration[1] < 0 and abs(m.calibration[1] - expected) < 0.015
    assert abs(math.remainder(est[-1, 2] - poses[-1, 2], 2 * math.pi)) < m.options.yaw_step_rad
    assert abs(odo[-1, 2] - poses[-1, 2]) > 0.1


def test_a_lone_wall_informs_across_it_only():
    """The match's information matrix for N points of a straight wall mapped beyond them:
    about N / sigma^2 across it (each point's error the field's width), next to nothing
    along it."""
    wall = np.stack([np.linspace(-2, 2, 81), np.full(81, 1.0)], 1)  # y = 1 m, robot frame
    m = ScanMatcher()
    m.insert(np.stack([np.linspace(-3, 3, 241), np.full(241, 1.0)], 1), (0.0, 0.0, 0.0))
    r = m.match(wall, (0.0, 0.0, 0.0))
    info = m.information(wall, r.pose)
    across = len(wall) / m.options.sigma_m**2
    assert 0.75 * across < info[1, 1] < 1.25 * across
    assert info[0, 0] < 0.05 * across


def test_fusion_corrects_across_a_wall_and_keeps_odometry_along_it():
    """After 1 m of odometry (its covariance grown), a wall 8 cm nearer than predicted and
    nothing to say along it: the fused pose moves across, not along."""
    wall = np.stack([np.linspace(-2, 2, 81), np.full(81, 1.0)], 1)
    m = ScanMatcher()
    m.correct(wall, (0.0, 0.0, 0.0))
    for k in range(1, 11):  # odometry drives 1 m along x, straight
        m.predict((0.1 * k, 0.0, 0.0))
    prior = (1.0 + 0.1, -0.08, 0.0)  # 10 cm along the wall, 8 cm away from it
    m.last_pose = (1.0, 0.0, 0.0)
    truth_view = np.stack([np.linspace(-3, 1, 81), np.full(81, 1.0)], 1)  # from x = 1 m
    r = m.correct(truth_view, prior)
    assert r.accepted
    assert abs(r.pose[1] - 0.0) < 0.5 * 0.08  # across: mostly corrected
    assert abs(r.pose[0] - prior[0]) < 0.02  # along: odometry's


def test_without_fusion_the_match_is_kept_as_it_is():
    opts = ScanMatcherOptions(match_variance_scale=0.0, calibrate_odometry=False)
    a, b = ScanMatcher(opts, center=(2, 1.5)), ScanMatcher(opts, center=(2, 1.5))
    truth = (1.5, 1.2, 0.3)
    a.correct(_room_scan(truth), truth)
    b.insert(_room_scan(truth), truth)
    prior = (1.55, 1.15, 0.33)
    assert a.correct(_room_scan(truth), prior).pose == b.match(_room_scan(truth), prior).pose


def _fuse_once(threshold, offset, information, covariance):
    """One fusion of a match ``offset`` (dx, dy, dyaw) from the prediction (0, 0, 0), with
    the given match information (3, 3) and prediction covariance (3, 3)."""
    m = ScanMatcher(ScanMatcherOptions(rejection_threshold=threshold, calibrate_odometry=False))
    cov = np.zeros((5, 5))
    cov[:3, :3] = covariance
    m.covariance = cov
    m.last_pose = (0.0, 0.0, 0.0)
    found = MatchResult(tuple(float(v) for v in offset), 0.9, True, 100)
    return m, m.fuse(found, (0.0, 0.0, 0.0), np.asarray(information, np.float64))


def test_the_innovation_distance_is_the_mahalanobis_distance_of_the_match():
    """With a full-rank match, the distance the gate compares is sqrt(z^T (P + J^-1)^-1 z),
    computed here directly with numpy's inverse."""
    rng = np.random.default_rng(4)
    for _ in range(20):
        a = rng.normal(size=(3, 3))
        p = a @ a.T * 1e-3 + np.diag([1e-4, 1e-4, 1e-5])
        b = rng.normal(size=(3, 3))
        j = b @ b.T * 1e3 + np.eye(3) * 10.0
        z = rng.normal(size=3) * 0.05
        m, _ = _fuse_once(math.inf, z, j, p)
        expected = math.sqrt(z @ np.linalg.inv(p + np.linalg.inv(j)) @ z)
        assert m.last_mahalanobis == pytest.approx(expected, rel=1e-3)  # fuse floors P by 1e-8


def test_a_match_beyond_the_gate_is_refused_and_one_within_it_fused():
    """A match 10 sigma from the prediction is refused with a gate of 3 (the pose and the
    covariance stay the prediction's) and fused without a gate; one 1 sigma away passes."""
    p = np.diag([0.01**2, 0.01**2, 0.005**2])
    j = np.diag([1 / 0.01**2, 1 / 0.01**2, 1 / 0.005**2])
    sigma = math.sqrt(0.01**2 + 0.01**2)  # of x: the prediction's and the match's
    far = (10 * sigma, 0.0, 0.0)
    m, r = _fuse_once(3.0, far, j, p)
    assert not r.accepted and r.pose == (0.0, 0.0, 0.0)
    assert np.allclose(m.covariance[:3, :3], p)
    assert m.last_mahalanobis == pytest.approx(10.0, rel=1e-3)
    _, r = _fuse_once(math.inf, far, j, p)
    assert r.accepted and r.pose[0] == pytest.approx(5 * sigma, rel=1e-3)  # halfway
    _, r = _fuse_once(3.0, (sigma, 0.0, 0.0), j, p)
    assert r.accepted


def test_the_gate_ignores_what_the_match_cannot_see():
    """A lone wall informs across it only (y): an innovation along it (x), however large, is
    not a disagreement, so the gate passes it."""
    p = np.diag([0.01**2, 0.01**2, 0.005**2])
    j = np.diag([0.0, 1 / 0.01**2, 0.0])
    m, r = _fuse_once(3.0, (0.5, 0.0, 0.0), j, p)
    assert r.accepted and m.last_mahalanobis == pytest.approx(0.0, abs=1e-9)
    m, r = _fuse_once(3.0, (0.0, 0.1, 0.0), j, p)
    assert not r.accepted


@pytest.mark.parametrize("value", [0.0, -1.0, float("nan")])
def test_the_rejection_threshold_is_validated(value):
    with pytest.raises(OptionError):
        ScanMatcherOptions(rejection_threshold=value)
