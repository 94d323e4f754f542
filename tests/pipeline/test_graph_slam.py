"""The pose graph's matching pieces: the likelihood field against its formula, and a scan that
moved by a known motion found where it moved (brute force over the same window agrees)."""

import math

import numpy as np
import pytest
from floorscan.mapping import pose_graph
from floorscan.pipeline.graph_slam import GraphSlam, likelihood_field, to_world


def test_the_likelihood_field_follows_its_formula():
    pts = np.array([[1.0, 1.0]])
    field, corner = likelihood_field(pts, (1.0, 1.0), 1.0, 0.05, 0.1)
    ys, xs = np.mgrid[0 : field.shape[0], 0 : field.shape[1]]
    cx, cy = corner[0] + (xs + 0.5) * 0.05, corner[1] + (ys + 0.5) * 0.05
    # the point's cell centre is where d = 0
    ci, cj = int((1.0 - corner[0]) / 0.05), int((1.0 - corner[1]) / 0.05)
    d = np.hypot(cx - (corner[0] + (ci + 0.5) * 0.05), cy - (corner[1] + (cj + 0.5) * 0.05))
    expected = np.where(d > 0.3, 0.0, np.exp(-0.5 * (d / 0.1) ** 2))
    np.testing.assert_allclose(field, expected, atol=0.02)
    assert likelihood_field(pts, (10.0, 10.0), 1.0, 0.05, 0.1) is None


def l_shape():
    """Points of two walls meeting at a corner, and a post: enough to fix x, y and yaw."""
    a = np.stack([np.linspace(0.5, 4.0, 80), np.full(80, 2.0)], 1)
    b = np.stack([np.full(60, 4.0), np.linspace(-1.5, 2.0, 60)], 1)
    c = np.stack(
        [1.5 + 0.1 * np.cos(np.linspace(0, 6.2, 20)), -1.0 + 0.1 * np.sin(np.linspace(0, 6.2, 20))],
        1,
    )
    return np.concatenate([a, b, c])


@pytest.mark.skipif(not pose_graph.AVAILABLE, reason="GTSAM is not installed")
def test_a_scan_is_found_where_it_moved_against_odometrys_wrong_guess():
    world = l_shape()
    slam = GraphSlam({"keyframe_distance_m": 5.0, "keyframe_rotation_rad": 3.0})
    start = (0.0, 0.0, 0.0)
    slam.add(world, start)  # seen from the origin: robot frame = world frame
    true_pose = (0.15, -0.1, 0.08)
    c, s = math.cos(true_pose[2]), math.sin(true_pose[2])
    rel = world - np.array(true_pose[:2])
    seen = np.stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]], 1)
    np.testing.assert_allclose(to_world(true_pose, seen), world, atol=1e-12)
    # odometry says the robot stood still
    pose = slam.add(seen, start)
    assert math.hypot(pose[0] - true_pose[0], pose[1] - true_pose[1]) < 0.03
    assert abs(pose[2] - true_pose[2]) < 0.012
    assert slam.matched == 1
    final = slam.finish()
    assert final.shape == (2, 3)
