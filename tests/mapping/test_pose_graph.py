"""The pose graph (GTSAM): a square driven with odometry that over-turns, closed by one exact
loop closure, must come back to the true square; a wrong loop closure among right ones must
weigh little (the Cauchy loss). Truth: the square's own geometry."""

import math

import numpy as np
import pytest
from floorscan.errors import ConfigError, OptionError
from floorscan.formats.trajectory import compose, relative
from floorscan.mapping import pose_graph
from floorscan.mapping.pose_graph import PoseGraph, PoseGraphOptions
from floorscan.pipeline.config import Config

needs_gtsam = pytest.mark.skipif(not pose_graph.AVAILABLE, reason="GTSAM is not installed")


def square(side=4.0, per_side=8):
    """True keyframe poses around a square (x, y, yaw), start included, end at the start."""
    poses, step = [(0.0, 0.0, 0.0)], side / per_side
    for _side in range(4):
        for _ in range(per_side):
            poses.append(compose(poses[-1], (step, 0.0, 0.0)))
        poses[-1] = compose(poses[-1], (0.0, 0.0, math.pi / 2))
    return poses


def odometry_steps(truth, turn_scale=1.05, drift=0.01):
    """The true steps with turns 5 % too large and 0.01 rad of heading drift per step."""
    return [
        (r[0], r[1], turn_scale * r[2] + drift)
        for r in (relative(a, b) for a, b in zip(truth, truth[1:]))
    ]


def build(truth, steps, **options):
    g = PoseGraph(PoseGraphOptions(**options))
    g.add_keyframe(truth[0])
    for s in steps:
        g.add_keyframe(s)
    return g


@needs_gtsam
def test_one_exact_loop_closure_brings_the_square_back():
    truth = square()
    # a loss as wide as 100 standard deviations: plain least squares, for a closure the
    # drift puts tens of standard deviations away (the default loss would weigh it little)
    g = build(truth, odometry_steps(truth), loop_robust_scale=100.0)
    end = len(truth) - 1
    before = np.hypot(*(g.poses[end, :2] - np.array(truth[end][:2])))
    assert before > 0.5  # the drift is real
    g.add_loop_closure(0, end, relative(truth[0], truth[end]))
    cost = g.error()
    g.optimize()
    assert g.error() < 0.1 * cost
    err = np.hypot(*(g.poses[:, :2] - np.array(truth)[:, :2]).T)
    assert err[end] < 0.05 and err.max() < 0.25 * before, (err.max(), before)
    assert g.loop_closures == 1


@needs_gtsam
def test_a_wrong_loop_closure_weighs_little_among_right_ones():
    truth = square()
    g = build(truth, odometry_steps(truth))
    n = len(truth)
    for j, k in [(0, n - 1), (1, n - 2), (2, n - 3)]:
        g.add_loop_closure(j, k, relative(truth[j], truth[k]))
    g.add_loop_closure(0, n - 2, (2.0, 1.5, 0.8))  # far from what the square allows
    g.optimize()
    err = np.hypot(*(g.poses[:, :2] - np.array(truth)[:, :2]).T)
    assert err.max() < 0.2, err.max()


@needs_gtsam
def test_a_loop_closure_must_join_two_existing_keyframes_in_order():
    g = build(square(), [])
    with pytest.raises(ValueError):
        g.add_loop_closure(0, 3, (0.0, 0.0, 0.0))


def test_without_gtsam_the_graph_is_a_config_error_naming_the_install(monkeypatch):
    monkeypatch.setattr(pose_graph, "gtsam", None)
    with pytest.raises(ConfigError, match=r"floorscan\[slam\]"):
        PoseGraph(PoseGraphOptions())


def test_options_come_from_rust_and_a_bad_one_is_named():
    o = PoseGraphOptions()
    # the config file's [slam.graph] is this type
    assert Config.from_toml("[slam.graph]\nloop_candidates = 3\n").slam.options()["graph"] == {
        **o.to_dict(),
        "loop_candidates": 3,
    }
    with pytest.raises(OptionError, match="loop_candidates"):
        PoseGraphOptions(loop_candidates=0)
    with pytest.raises(OptionError, match="keyframe_distance_m"):
        PoseGraphOptions(keyframe_distance_m=-1.0)
    # the field covers the scan's reach and the wider search
    assert o.field_half_side_m() >= o.range_max_m + max(o.search_xy_m, o.loop_search_xy_m)


def test_a_closure_is_wide_only_along_what_its_match_cannot_see():
    """Analytic: an information matrix that constrains world y (and yaw) but not world x (a
    corridor along x passed again): the closure's covariance, read in the later keyframe's
    frame, is loop_sigma_xy_m across the corridor and MAX_WEAK_SIGMA_FACTOR times it along;
    turned by 90 degrees, the axes swap; without information or with the option off, round."""
    o = PoseGraphOptions()
    info = np.diag([0.0, 400.0, 50.0])
    s, wide = o.loop_sigma_xy_m, pose_graph.MAX_WEAK_SIGMA_FACTOR * o.loop_sigma_xy_m
    cov = pose_graph.loop_covariance(o, info, 0.0)
    np.testing.assert_allclose(np.sqrt(np.diag(cov)), [wide, s, o.loop_sigma_yaw_rad])
    turned = pose_graph.loop_covariance(o, info, math.pi / 2)
    np.testing.assert_allclose(np.sqrt(np.diag(turned)), [s, wide, o.loop_sigma_yaw_rad])
    assert abs(turned[0, 1]) < 1e-12
    # half the information along x: sqrt(2) wider there
    half = pose_graph.loop_covariance(o, np.diag([200.0, 400.0, 50.0]), 0.0)
    np.testing.assert_allclose(np.sqrt(half[0, 0]), s * math.sqrt(2.0))
    for c in (
        pose_graph.loop_covariance(o, None, 0.3),
        pose_graph.loop_covariance(PoseGraphOptions(loop_information=False), info, 0.3),
        pose_graph.loop_covariance(o, np.zeros((3, 3)), 0.3),
    ):
        np.testing.assert_allclose(np.sqrt(np.diag(c)), [s, s, o.loop_sigma_yaw_rad])


@needs_gtsam
def test_closures_slid_along_a_corridor_do_not_pull_the_graph_along_it():
    """Exact odometry around the square, and three closures that slid 0.8 m along the later
    keyframe's heading (what a plain corridor's match gives), each with the information of a
    match that sees only the corridor's walls: weighed by their information, they leave the
    square where odometry has it; weighed round, they pull it along."""
    truth = square()
    n = len(truth)

    def solve(**options):
        g = build(truth, odometry_steps(truth, turn_scale=1.0, drift=0.0), **options)
        for j, k in [(0, n - 1), (1, n - 2), (2, n - 3)]:
            slid = compose(truth[k], (0.8, 0.0, 0.0))
            along = np.array([math.cos(slid[2]), math.sin(slid[2])])
            info = np.zeros((3, 3))
            info[:2, :2] = 400.0 * (np.eye(2) - np.outer(along, along))  # across only
            info[2, 2] = 50.0
            g.add_loop_closure(j, k, relative(truth[j], slid), info)
        g.optimize()
        return np.hypot(*(g.poses[:, :2] - np.array(truth)[:, :2]).T).max()

    weighed, round_ = solve(), solve(loop_information=False)
    assert weighed < 0.02 and round_ > 0.1, (weighed, round_)
