"""The scan matcher's filter in the Rust core against the numpy code it replaced
(tests/scan_matcher_reference.py): the match's information matrix
(``floorscan_core::match_information``) on random fields, points and poses, points whose
cells leave the field, no points, no field, negative curvatures cut; the prediction and the
fusion (``floorscan_core::match_filter``) from random states; and whole runs of ``correct``. Equal to
rounding: the information to 1e-9 of its largest entry; from random states the predicted and
fused poses to 1e-12 m, the calibration to 1e-10, the covariance to 1e-10 (fusion) and 1e-12
(prediction) of its largest entry; over whole runs, where the likelihood fields differ by
float32 rounding (OpenCV's distance transform and numpy's float32 exp there, the hits' stamps
computed in float64 here), the poses to 1e-7 m and rad."""

from __future__ import annotations

import math

import numpy as np
import pytest
from floorscan._native.mapping import match_information
from floorscan.errors import FloorscanError
from floorscan.mapping.scan_matcher import MatchResult, ScanMatcher, ScanMatcherOptions
from scan_matcher_reference import ReferenceScanMatcher


def _close(a, b, rtol):
    """``a`` equals ``b`` to ``rtol`` of ``b``'s largest entry (or 1e-300)."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return np.abs(a - b).max() <= rtol * max(np.abs(b).max(), 1e-300)


def _pair(options=None):
    options = options or ScanMatcherOptions(size_m=8.0)
    return (
        ScanMatcher(options, center=(0.3, -0.2)),
        ReferenceScanMatcher(options, center=(0.3, -0.2)),
    )


def _information(ref, pts, pose):
    """The core's information matrix on the reference's kept field and matched points."""
    if ref._cache is None:
        return np.zeros((3, 3))
    field, i0, j0 = ref._cache
    origin = (ref.origin_m[0] + i0 * ref.cell, ref.origin_m[1] + j0 * ref.cell)
    return match_information(
        np.ascontiguousarray(field),
        origin,
        ref.cell,
        ref._matched_points(pts),
        tuple(float(v) for v in pose),
        ref.options.yaw_step_rad,
    )


def _random_field(rng, h, w):
    """A field of smooth bumps, some flat zero areas and cell noise, float32 in [0, 1]."""
    y, x = np.mgrid[0:h, 0:w]
    f = np.zeros((h, w))
    for _ in range(int(rng.integers(1, 6))):
        cx, cy, s = rng.uniform(0, w), rng.uniform(0, h), rng.uniform(1, 6)
        f += np.exp(-0.5 * ((x - cx) ** 2 + (y - cy) ** 2) / s**2)
    f += rng.uniform(0, 0.2, (h, w)) * (rng.uniform() < 0.5)
    f[rng.uniform(size=(h, w)) < 0.1] = 0.0
    return np.clip(f, 0, 1).astype(np.float32)


@pytest.mark.parametrize("seed", range(60))
def test_the_information_matrix_equals_numpys(seed):
    rng = np.random.default_rng(seed)
    ours, ref = _pair()
    h, w = (int(v) for v in rng.integers(2, 90, 2))
    field = _random_field(rng, h, w)
    i0, j0 = (int(v) for v in rng.integers(0, 200, 2))
    ref._cache = (field, i0, j0)
    # poses over the field and around its edges; points near and beyond them, some not
    # finite, some beyond the range limit, sometimes more than max_points
    lo = np.array(ref.origin_m) + np.array([i0, j0]) * ref.cell
    size = np.array([w, h]) * ref.cell
    pose = (*(lo + rng.uniform(-0.3, 1.3, 2) * size), rng.uniform(-math.pi, math.pi))
    n = int(rng.integers(0, 700))
    pts = rng.uniform(-1.5, 1.5, (n, 2)) * max(size.max(), 0.5)
    pts[rng.uniform(size=n) < 0.02] = np.nan
    got, want = _information(ref, pts, pose), ref.information(pts, pose)
    assert got.shape == (3, 3) and got.dtype == np.float64
    assert np.array_equal(got, got.T)  # exactly symmetric
    assert _close(got, want, 1e-9), (got, want)
    assert np.linalg.eigvalsh(got).min() >= -1e-9 * max(np.abs(got).max(), 1e-300)


def test_negative_curvatures_are_cut_as_numpy_cuts_them():
    """A field of isolated bright cells (the points between them see valleys and saddles):
    of 40 poses, most matrices are rank-deficient (cut), and each equals numpy's."""
    rng = np.random.default_rng(3)
    ours, ref = _pair()
    field = np.zeros((60, 60), np.float32)
    field[rng.integers(0, 60, 80), rng.integers(0, 60, 80)] = 1.0
    ref._cache = (field, 10, 20)
    cut = 0
    for _ in range(40):
        pts = rng.uniform(-0.6, 0.6, (30, 2))
        pose = (ref.origin_m[0] + 40 * ref.cell, ref.origin_m[1] + 50 * ref.cell, 0.2)
        got, want = _information(ref, pts, pose), ref.information(pts, pose)
        assert _close(got, want, 1e-9)
        w = np.linalg.eigvalsh(want)
        cut += int(w.min() < 1e-9 * w.max())
    assert cut >= 10


def test_no_points_no_field_and_points_off_the_field_give_zeros():
    ours, ref = _pair()
    pose = (0.0, 0.0, 0.0)
    assert np.array_equal(ours.information(np.zeros((0, 2)), pose), np.zeros((3, 3)))
    field = np.ones((40, 40), np.float32)
    ref._cache = (field, 100, 100)
    for pts in (np.zeros((0, 2)), np.full((5, 2), np.nan), np.full((5, 2), 2.9)):
        got = _information(ref, pts, pose)
        assert np.array_equal(got, np.zeros((3, 3)))
        assert np.array_equal(ref.information(pts, pose), np.zeros((3, 3)))
    ref._cache = (np.zeros((0, 0), np.float32), 0, 0)
    pts = np.ones((5, 2))
    assert np.array_equal(_information(ref, pts, pose), ref.information(pts, pose))
    # a field of one row or column: every point's cells leave it (numpy's reading indexed
    # past such a field's end)
    for shape in ((1, 40), (40, 1)):
        ref._cache = (np.ones(shape, np.float32), 100, 100)
        got = _information(
            ref, np.zeros((5, 2)), (ref.origin_m[0] + 2.51, ref.origin_m[1] + 2.51, 0)
        )
        assert np.array_equal(got, np.zeros((3, 3)))


def test_bad_native_arguments_are_errors():
    f, pts = np.zeros((4, 4), np.float32), np.zeros((3, 2))
    with pytest.raises(FloorscanError):
        match_information(f, (0.0, 0.0), 0.0, pts, (0.0, 0.0, 0.0), 0.01)
    with pytest.raises(FloorscanError):
        match_information(f, (0.0, 0.0), 0.1, pts, (0.0, 0.0, 0.0), -1.0)
    with pytest.raises(FloorscanError):
        match_information(f, (0.0, 0.0), 0.1, pts, (math.nan, 0.0, 0.0), 0.01)
    with pytest.raises(FloorscanError):
        match_information(f, (0.0, 0.0), 0.1, np.zeros((3, 3)), (0.0, 0.0, 0.0), 0.01)
    with pytest.raises(FloorscanError):
        match_information(f[:, ::2], (0.0, 0.0), 0.1, pts, (0.0, 0.0, 0.0), 0.01)


def _random_state(rng, m, calibrate):
    """A random positive definite covariance (5, 5) with the filter's scales, calibration and
    last pose, set on ``m``."""
    scales = np.array([0.1, 0.1, 0.03, 0.05, 0.03]) * 10 ** rng.uniform(-3, 0, 5)
    a = rng.normal(size=(5, 5)) * scales[:, None]
    cov = a @ a.T + np.diag(scales**2) * 1e-3
    if not calibrate:  # as the prediction leaves it: the calibration's variances only
        cov[3:, :] = 0.0
        cov[:, 3:] = 0.0
        cov[3, 3], cov[4, 4] = 10 ** rng.uniform(-10, -8, 2)
    m.covariance = cov
    m.calibration = (float(rng.normal(0, 0.05)), float(rng.normal(0, 0.02)))
    m.last_pose = (float(rng.uniform(-5, 5)), float(rng.uniform(-5, 5)), float(rng.uniform(-4, 4)))


OPTIONS = [
    ScanMatcherOptions(size_m=8.0),
    ScanMatcherOptions(size_m=8.0, match_variance_scale=4.0),
    ScanMatcherOptions(size_m=8.0, calibrate_odometry=False),
    ScanMatcherOptions(size_m=8.0, match_variance_scale=0.0),
]


@pytest.mark.parametrize("options", OPTIONS)
def test_the_prediction_equals_numpys_from_random_states(options):
    rng = np.random.default_rng(5)
    ours, ref = _pair(options)
    for _ in range(200):
        _random_state(rng, ours, options.calibrate_odometry)
        ref.covariance, ref.calibration, ref.last_pose = (
            ours.covariance,
            ours.calibration,
            ours.last_pose,
        )
        a = ours.last_pose
        d, turn = rng.uniform(-0.15, 0.3), rng.uniform(-0.4, 0.4) * (rng.uniform() < 0.8)
        side = rng.uniform(-0.02, 0.02)
        prior = (
            a[0] + d * math.cos(a[2]) - side * math.sin(a[2]),
            a[1] + d * math.sin(a[2]) + side * math.cos(a[2]),
            a[2] + turn,
        )
        got, want = ours.predict(prior), ref.predict(prior)
        assert np.allclose(got, want, rtol=0, atol=1e-12)
        assert np.allclose(ref.last_pose, want, rtol=0, atol=1e-12)
        assert _close(ours.covariance, ref.covariance, 1e-12)


def _random_information(rng):
    """A positive semi-definite (3, 3) matrix of the matcher's scales (up to 1e6 / m^2), of
    rank 0 to 3 (a corridor informs across itself only)."""
    rank = int(rng.integers(0, 4))
    v = rng.normal(size=(3, rank)) * np.array([[1.0], [1.0], [0.5]]) * 10 ** rng.uniform(0, 3)
    return v @ v.T


@pytest.mark.parametrize("options", OPTIONS)
def test_the_fusion_equals_numpys_from_random_states(options):
    rng = np.random.default_rng(9)
    ours, ref = _pair(options)
    for k in range(300):
        _random_state(rng, ours, options.calibrate_odometry)
        ref.covariance, ref.calibration, ref.last_pose = (
            ours.covariance,
            ours.calibration,
            ours.last_pose,
        )
        prior = ours.last_pose
        found = (
            prior[0] + rng.normal(0, 0.05),
            prior[1] + rng.normal(0, 0.05),
            prior[2] + rng.normal(0, 0.03) + 2 * math.pi * (k % 3 == 0),
        )
        result = MatchResult(found, 0.7, bool(k % 7), 100)
        info = _random_information(rng)
        got, want = ours.fuse(result, prior, info), ref.fuse(result, prior, info)
        assert got.accepted == want.accepted and got.score == want.score
        assert np.allclose(got.pose, want.pose, rtol=0, atol=1e-12)
        assert ours.last_pose == got.pose
        # numpy inverted the covariance itself (condition numbers to 1e9 here): equal to its
        # rounding (measured: 8e-12 in the calibration, 5e-13 of the covariance's largest
        # entry)
        assert np.allclose(ours.calibration, ref.calibration, rtol=0, atol=1e-10)
        assert _close(ours.covariance, ref.covariance, 1e-10)


@pytest.mark.parametrize("options", OPTIONS[:3])
def test_whole_runs_of_correct_equal_numpys(options):
    """Scans of a room from drifting odometry poses: the same matches accepted, poses,
    calibration and covariance equal to rounding, frame after frame."""
    rng = np.random.default_rng(21)
    ours, ref = _pair(options)
    a = np.linspace(-2.0, 2.0, 200)
    room = np.stack([2.5 * np.cos(a), 1.5 * np.sin(a) + 0.3 * np.sin(3 * a)], 1)
    truth = np.array([0.0, 0.0, 0.0])
    odo = truth.copy()
    accepted = 0
    for k in range(40):
        step = np.array([0.05, 0.0, 0.04 * math.sin(0.3 * k)])
        c, s = math.cos(truth[2]), math.sin(truth[2])
        truth += [c * step[0], s * step[0], step[2]]
        c, s = math.cos(odo[2]), math.sin(odo[2])
        odo += [c * step[0] * 1.01, s * step[0] * 1.01, step[2] * 1.03 + rng.normal(0, 0.002)]
        c, s = math.cos(truth[2]), math.sin(truth[2])
        world = room + rng.normal(0, 0.01, room.shape)
        pts = (world - truth[:2]) @ np.array([[c, -s], [s, c]])
        got, want = ours.correct(pts, tuple(odo)), ref.correct(pts, tuple(odo))
        assert got.accepted == want.accepted and got.points == want.points
        assert np.allclose(got.pose, want.pose, rtol=0, atol=1e-7), k
        assert np.allclose(ours.calibration, ref.calibration, rtol=0, atol=1e-7)
        assert _close(ours.covariance, ref.covariance, 1e-6)
        assert np.array_equal(ours.hits, ref.hits)
        accepted += got.accepted
    assert accepted > 20


def test_without_calibration_a_still_robot_fuses_the_pose_alone():
    """Odometry's calibration not estimated and the robot not moved: the state's calibration
    rows are all 0 (numpy's inverse of the covariance failed there); the pose fuses as the
    3-state filter's information form says."""
    m = ScanMatcher(ScanMatcherOptions(size_m=8.0, calibrate_odometry=False))
    m.last_pose = (1.0, 2.0, 0.5)
    assert m.predict((1.0, 2.0, 0.5)) == (1.0, 2.0, 0.5)
    p = np.diag([1e-4, 4e-4, 1e-5, 0.0, 0.0])
    p[0, 2] = p[2, 0] = 1e-5
    m.covariance = p
    info = np.array([[2e4, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1e3]])
    found = (1.03, 1.98, 0.52)
    got = m.fuse(MatchResult(found, 0.8, True, 50), (1.0, 2.0, 0.5), info)
    p3 = p[:3, :3] + np.diag([1e-8, 1e-8, 1e-10])
    post = np.linalg.inv(np.linalg.inv(p3) + info)
    want = np.array([1.0, 2.0, 0.5]) + post @ info @ (np.array(found) - [1.0, 2.0, 0.5])
    assert np.allclose(got.pose, want, rtol=0, atol=1e-12)
    assert np.allclose(m.covariance[:3, :3], 0.5 * (post + post.T), rtol=1e-9, atol=0)
    assert not m.covariance[3:].any() and not m.covariance[:, 3:].any()
