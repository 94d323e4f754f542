"""The scan matcher in the Rust core against the numpy and OpenCV code it replaced
(tests/scan_matcher_reference.py): the same hit counts bit for bit, the same likelihood field
to float32 rounding (OpenCV's exact distance transform there, the hits' stamps here), the same
matches, over random scans from drifting poses, with points off the map, non-finite and beyond
the range limit, and saturating counts."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan.errors import FloorscanError
from floorscan.mapping.scan_matcher import ScanMatcher, ScanMatcherOptions
from scan_matcher_reference import ReferenceScanMatcher


def _scan(rng, n):
    a = np.linspace(-1.2, 1.2, n)
    r = rng.uniform(0.3, 3.6, n) * (1 + 0.2 * np.sin(4 * a))
    pts = np.stack([r * np.cos(a), r * np.sin(a)], 1)
    pts[rng.uniform(size=n) < 0.03] = np.nan
    pts[rng.uniform(size=n) < 0.02, 0] = np.inf
    return pts


@pytest.mark.parametrize(
    "options",
    [
        ScanMatcherOptions(size_m=8.0),
        ScanMatcherOptions(size_m=6.0, cell_size_m=0.05, novelty_m=0.0, sigma_m=0.1),
        ScanMatcherOptions(size_m=10.0, novelty_m=0.3, range_max_m=2.0),
    ],
)
def test_random_scans_store_the_same_hits_field_and_matches(options):
    rng = np.random.default_rng(11)
    ours = ScanMatcher(options, center=(0.5, -0.5))
    ref = ReferenceScanMatcher(options, center=(0.5, -0.5))
    pose = (0.0, 0.0, 0.0)
    walls = _scan(rng, 160)
    compared = 0
    for k in range(25):
        pose = (pose[0] + 0.15, pose[1] + rng.normal(0, 0.05), pose[2] + rng.normal(0, 0.1))
        pts = walls if k % 3 else _scan(rng, int(rng.integers(0, 300)))
        a, b = ours.correct(pts, pose), ref.correct(pts, pose)
        assert (a.accepted, a.points) == (b.accepted, b.points)
        assert np.allclose(a.pose, b.pose, rtol=0, atol=1e-7) and abs(a.score - b.score) < 1e-6
        assert np.array_equal(ours.hits, ref.hits)
        if ref._cache is not None:
            field, i0, j0 = ours.field
            assert (i0, j0) == ref._cache[1:] and field.shape == ref._cache[0].shape
            assert np.abs(field - ref._cache[0]).max() < 1e-6
            compared += 1
    # the same cell many times: counts saturate at 255
    many = np.tile([[1.0, 0.0]], (300, 1))
    home = (0.0, 0.0, 0.0)
    assert ours.insert(many, home) == ref.insert(many, home) == 300
    assert np.array_equal(ours.hits, ref.hits) and ours.hits.max() == 255
    assert compared >= 5


def test_bad_native_arguments_are_errors():
    from floorscan._native.mapping import ScanMatcher as Native

    o = ScanMatcherOptions(size_m=8.0).to_dict()
    with pytest.raises(FloorscanError):
        Native({**o, "cell_size_m": 0.0}, (0.0, 0.0))
    with pytest.raises(FloorscanError):
        Native(o, (float("nan"), 0.0))
    m = Native(o, (0.0, 0.0))
    with pytest.raises(FloorscanError):
        m.correct(np.zeros((4, 3)), (0.0, 0.0, 0.0))
    with pytest.raises(FloorscanError):
        m.correct(np.zeros((4, 2)), (0.0, float("inf"), 0.0))
    with pytest.raises(FloorscanError):
        m.fuse(((0.0, 0.0, 0.0), 0.5, True, 50), (0.0, 0.0, 0.0), np.zeros((2, 2)))
    with pytest.raises(FloorscanError):
        m.covariance = np.zeros((4, 4))
    with pytest.raises(FloorscanError):
        m.last_pose = (0.0, float("nan"), 0.0)
    assert m.frames == 0  # nothing stored by the refused calls
