"""The scan matcher's storing (novelty test, hit counts, stamps into the cached likelihood
field) as first written with numpy: the reference the Rust core (``floorscan_core::hit_map``)
must equal (tests/drive/test_scan_matcher_native.py)."""

from __future__ import annotations

import math

import numpy as np
from floorscan.drive.scan_matcher import ScanMatcher, _disc


class ReferenceScanMatcher(ScanMatcher):
    """:class:`~floorscan.drive.scan_matcher.ScanMatcher` storing with numpy."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        o = self.options
        r = int(math.floor(3.0 * o.sigma_m / self.cell))
        self._stamp_offsets = _disc(r, self.cell, 3.0 * o.sigma_m)[:2]
        r = int(math.floor(o.novelty_m / self.cell))
        self._novelty_offsets = _disc(r, self.cell, r * self.cell)[:2] if r > 0 else None

    def _cells(self, x, y):
        i = np.floor((np.asarray(x) - self.origin_m[0]) / self.cell).astype(np.int64)
        j = np.floor((np.asarray(y) - self.origin_m[1]) / self.cell).astype(np.int64)
        return i, j

    def _stamp(self, i, j) -> None:
        if self._cache is None or len(i) == 0:
            return
        field, i0, j0 = self._cache
        h, w = field.shape
        di, dj = self._stamp_offsets
        val = self._stamp_values
        ii = (i - i0)[:, None] + di[None, :]
        jj = (j - j0)[:, None] + dj[None, :]
        inside = (ii >= 0) & (ii < w) & (jj >= 0) & (jj < h)
        vals = np.broadcast_to(val[None, :], ii.shape)[inside]
        flat = (jj[inside] * w + ii[inside]).astype(np.int64)
        order = np.argsort(vals, kind="stable")
        flat, vals = flat[order], vals[order]
        view = field.reshape(-1)
        view[flat] = np.maximum(view[flat], vals)

    def insert(self, points_robot, pose, *, novel_only: bool = False) -> int:
        pts = self._usable(points_robot)
        c, s = math.cos(pose[2]), math.sin(pose[2])
        i, j = self._cells(
            pose[0] + c * pts[:, 0] - s * pts[:, 1], pose[1] + s * pts[:, 0] + c * pts[:, 1]
        )
        ok = (i >= 0) & (i < self.n) & (j >= 0) & (j < self.n)
        i, j = i[ok], j[ok]
        if novel_only and self.frames > 0 and self._novelty_offsets is not None and len(i):
            di, dj = self._novelty_offsets
            ni = np.clip(i[:, None] + di[None, :], 0, self.n - 1)
            nj = np.clip(j[:, None] + dj[None, :], 0, self.n - 1)
            new = ~(self.hits[nj, ni] > 0).any(axis=1)
            i, j = i[new], j[new]
        self._stamp(i, j)
        flat, counts = np.unique(j * self.n + i, return_counts=True)
        view = self.hits.reshape(-1)
        view[flat] = np.minimum(view[flat].astype(np.int64) + counts, 255).astype(np.uint8)
        self.frames += 1
        if self._cache is not None:
            self._cache_nonzero = bool(self._cache[0].any())
        return len(i)
