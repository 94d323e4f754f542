"""The reference avoidance map's vectorised hit drawing (tests/avoidance_map_reference.py, which
the Rust core equals) against brute force over every cell: a disc
marks exactly the cells whose centre lies within its radius; a face segment marks every cell
it passes through."""

from __future__ import annotations

import numpy as np
from avoidance_map_reference import stamp_hits as _stamp_hits


def _arc(rng, count=160):
    a = np.linspace(-1.2, 1.2, count)
    r = 40 + 10 * np.sin(3 * a) + rng.normal(0, 0.5, a.size)
    return 60 + r * np.cos(a), 10 + r * np.sin(a)


def test_discs_are_the_cells_whose_centres_lie_within_the_radius():
    rng = np.random.default_rng(7)
    n = 120
    cx, cy = _arc(rng)
    rad = rng.uniform(0.5, 3.0, cx.size)
    values = np.arange(cx.size, dtype=np.float32)  # which reading drew a cell
    ok = rng.uniform(size=cx.size) > 0.1
    ours = np.full((n, n), np.nan, np.float32)
    _stamp_hits(ours, cx, cy, rad, values, ok, np.zeros(cx.size, bool))
    jj, ii = np.mgrid[0:n, 0:n]
    covered = np.zeros((n, n), bool)
    for k in np.nonzero(ok)[0]:
        d = np.hypot(ii + 0.5 - cx[k], jj + 0.5 - cy[k])
        mine = d <= rad[k]
        covered |= mine
        # a cell drawn by reading k lies within reading k's radius
        assert np.all(np.hypot(ii + 0.5 - cx[k], jj + 0.5 - cy[k])[ours == k] <= rad[k] + 1e-9)
    assert np.array_equal(np.isfinite(ours), covered)


def test_face_segments_are_8_connected_chains_of_cells_on_the_segment():
    import cv2

    n = 50
    cx, cy = np.array([5.2, 30.7, 12.0]), np.array([5.5, 22.1, 40.3])
    ok = np.array([True, True, True])
    near = np.array([True, True, False])
    rad = np.full(3, 0.01)  # discs of no cell: the segments alone
    values = np.array([2.0, 1.0, 3.0], np.float32)
    ours = np.full((n, n), np.nan, np.float32)
    _stamp_hits(ours, cx, cy, rad, values, ok, near)
    drawn = np.isfinite(ours)
    jj, ii = np.nonzero(drawn)
    # every drawn cell's centre is within half a diagonal of one of the two segments
    px, py = ii + 0.5, jj + 0.5
    dist = np.full(px.shape, np.inf)
    for k in (0, 1):
        ax, ay, bx, by = cx[k], cy[k], cx[k + 1], cy[k + 1]
        t = np.clip(
            ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2),
            0,
            1,
        )
        dist = np.minimum(dist, np.hypot(px - (ax + t * (bx - ax)), py - (ay + t * (by - ay))))
    assert dist.max() <= np.sqrt(2) / 2 + 1e-9
    # the ends are drawn and joined: one 8-connected chain holds all three points' cells
    count, labels = cv2.connectedComponents(drawn.astype(np.uint8), connectivity=8)
    ends = {labels[int(np.floor(cy[k])), int(np.floor(cx[k]))] for k in range(3)}
    assert count == 2 and ends == {1}
    # each segment carries the smaller value of its two ends
    assert set(np.unique(ours[drawn]).tolist()) <= {1.0, 2.0}
