"""The scan matcher against geometry it must recover: a scan of a room stored at a known pose
is found again from a perturbed odometry pose; a lone straight wall fixes only what it can."""

from __future__ import annotations

import math

import numpy as np
import pytest
from floorscan.drive.scan_matcher import ScanMatcher, ScanMatcherOptions
from floorscan.errors import OptionError


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
    for _ in range(12):
        # odometry says the robot turned 0.01 rad more than it did, each frame
        estimate = (estimate[0], estimate[1], estimate[2] + 0.01)
        estimate = m.correct(_room_scan(truth), estimate).pose
    assert abs(estimate[2] - truth[2]) <= m.options.yaw_step_rad


def test_the_cached_field_with_new_hits_stamped_equals_a_fresh_field():
    m = ScanMatcher(center=(2, 1.5))
    m.insert(_room_scan((1.5, 1.2, 0.3)), (1.5, 1.2, 0.3))
    cached, i0, j0 = m._cached_field(1.5, 1.2, 3.3)
    m.insert(_room_scan((2.5, 1.0, 2.0)), (2.6, 1.1, 2.05))  # a shifted copy: new hits
    fresh, f0, g0 = m._field(1.5, 1.2, 3.3 + 1.0)
    assert (i0, j0) == (f0, g0)
    assert np.abs(m._cache[0] - fresh).max() < 1e-5


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
