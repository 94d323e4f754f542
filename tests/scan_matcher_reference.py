"""The scan matcher's storing (novelty test, hit counts, stamps into the cached likelihood
field) as first written with numpy: the reference the Rust core (``floorscan_core::hit_map``)
must equal (tests/mapping/test_scan_matcher_native.py); its filter (the odometry prediction, the
match's information matrix, the fusion) as first written with numpy: the reference of the Rust
core's ``floorscan_core::match_information`` and of the filter's algebra on floats
(tests/mapping/test_scan_matcher_filter.py)."""

from __future__ import annotations

import math

import numpy as np
from floorscan.mapping.scan_matcher import MatchResult, ScanMatcher, _disc


class ReferenceScanMatcher(ScanMatcher):
    """:class:`~floorscan.mapping.scan_matcher.ScanMatcher` storing with numpy."""

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


class ReferenceFilter(ScanMatcher):
    """:class:`~floorscan.mapping.scan_matcher.ScanMatcher` predicting, reading the match's
    information and fusing with numpy, as first written (``covariance`` set through its
    property)."""

    def predict(self, prior):
        """The prediction for the frame whose odometry pose, carried by the last correction,
        is ``prior`` (world_from_robot, the pose kept last composed with odometry's
        increment): the increment's turn corrected by the estimated turn scale error and
        heading drift per metre, the state's covariance grown as an extended Kalman filter
        predicts (each wheel's travel errs by ``odometry_wheel_sigma`` sqrt(|travel|), their
        mean is the distance driven, their difference over the wheelbase the turn).
        Returns the corrected prior."""
        o = self.options
        prior = tuple(float(v) for v in prior[:3])
        if self._last is None:
            self._last = prior
            return prior
        a = self._last
        c, s = math.cos(a[2]), math.sin(a[2])
        wx, wy = prior[0] - a[0], prior[1] - a[1]
        d = c * wx + s * wy  # signed distance driven (robot frame x)
        dth = math.remainder(prior[2] - a[2], 2 * math.pi)
        g, k = self.calibration
        extra = g * dth + k * d  # the turn odometry misses
        cr, sr = math.cos(0.5 * extra), math.sin(0.5 * extra)
        wx, wy = cr * wx - sr * wy, sr * wx + cr * wy
        pred = (a[0] + wx, a[1] + wy, a[2] + dth + extra)
        if not (o.calibrate_odometry and o.match_variance_scale > 0):
            pred = prior  # nothing to correct: the caller's prior as it is
        b = o.odometry_wheelbase_m
        vl = o.odometry_wheel_sigma**2 * abs(d - 0.5 * b * dth)
        vr = o.odometry_wheel_sigma**2 * abs(d + 0.5 * b * dth)
        motion = np.array(
            [[0.25 * (vl + vr), 0.5 * (vr - vl) / b], [0.5 * (vr - vl) / b, (vl + vr) / b**2]]
        )
        h = a[2] + 0.5 * (dth + extra)
        gm = np.zeros((5, 2))
        gm[0, 0], gm[1, 0], gm[2, 1] = math.cos(h), math.sin(h), 1.0
        f = np.eye(5)
        f[0, 2], f[1, 2] = -wy, wx
        f[2, 3], f[2, 4] = dth, d
        f[0, 3], f[1, 3] = -wy * 0.5 * dth, wx * 0.5 * dth
        f[0, 4], f[1, 4] = -wy * 0.5 * d, wx * 0.5 * d
        q = gm @ motion @ gm.T
        q[3, 3] = o.calibration_drift**2 * abs(dth)
        q[4, 4] = o.calibration_drift**2 * abs(d)
        self.covariance = f @ self.covariance @ f.T + q
        self._last = pred
        return pred

    def information(self, points_robot: np.ndarray, pose) -> np.ndarray:
        """The information matrix (3, 3) of the scan's match at ``pose``: minus the Hessian of
        the sum of field values (read bilinearly as the search reads them) at the points over
        (x, y, yaw), by central differences of a cell and a yaw step, with its negative
        eigenvalues cut to 0. Each point on a wall adds 1 / sigma_m^2 across it."""
        if self._cache is None:
            return np.zeros((3, 3))
        field, i0, j0 = self._cache
        pts = self._usable(points_robot)
        if len(pts) > self.options.max_points:
            idx = np.linspace(0, len(pts) - 1, int(self.options.max_points)).round()
            pts = pts[idx.astype(np.int64)]
        if field.size == 0 or len(pts) == 0:
            return np.zeros((3, 3))
        h = np.array([self.cell, self.cell, self.options.yaw_step_rad])
        offsets = [np.zeros(3)]
        for i in range(3):
            e = np.zeros(3)
            e[i] = h[i]
            offsets += [e, -e]
        for i in range(3):
            for j in range(i + 1, 3):
                for si in (1, -1):
                    for sj in (1, -1):
                        e = np.zeros(3)
                        e[i], e[j] = si * h[i], sj * h[j]
                        offsets.append(e)
        poses = np.asarray(pose[:3], np.float64)[None, :] + np.array(offsets)
        c, s = np.cos(poses[:, 2:3]), np.sin(poses[:, 2:3])
        x = poses[:, 0:1] + c * pts[None, :, 0] - s * pts[None, :, 1]
        y = poses[:, 1:2] + s * pts[None, :, 0] + c * pts[None, :, 1]
        fx = (x - self.origin_m[0]) / self.cell - i0 - 0.5
        fy = (y - self.origin_m[1]) / self.cell - j0 - 0.5
        ii, jj = np.floor(fx).astype(np.int64), np.floor(fy).astype(np.int64)
        ax, ay = fx - ii, fy - jj
        hgt, wid = field.shape
        # the four cells around each point, flat; a point whose cells leave the field reads
        # 0 there (the field covers the search window with a margin: none do in the drive)
        inside = (ii >= 0) & (jj >= 0) & (ii < wid - 1) & (jj < hgt - 1)
        base = np.where(inside, jj * wid + ii, 0)
        flat = field.ravel()
        v = np.where(
            inside,
            (1 - ax) * (1 - ay) * flat[base]
            + ax * (1 - ay) * flat[base + 1]
            + (1 - ax) * ay * flat[base + wid]
            + ax * ay * flat[base + wid + 1],
            0.0,
        ).sum(axis=1)
        hess = np.zeros((3, 3))
        for i in range(3):
            hess[i, i] = (v[1 + 2 * i] - 2 * v[0] + v[2 + 2 * i]) / h[i] ** 2
        k = 7
        for i in range(3):
            for j in range(i + 1, 3):
                pp, pm, mp, mm = v[k : k + 4]
                hess[i, j] = hess[j, i] = (pp - pm - mp + mm) / (4 * h[i] * h[j])
                k += 4
        w, vec = np.linalg.eigh(-hess)
        return (vec * np.clip(w, 0.0, None)) @ vec.T

    def fuse(self, result: MatchResult, prior, information: np.ndarray) -> MatchResult:
        """The accepted match fused with the prediction ``prior`` (``predict`` first) in
        information form: the match's information is ``information`` /
        ``match_variance_scale``; the covariance shrinks accordingly."""
        o = self.options
        prior = tuple(float(v) for v in prior[:3])
        if not result.accepted or o.match_variance_scale == 0:
            self._last = tuple(result.pose)
            return result
        info = np.zeros((5, 5))
        info[:3, :3] = information / o.match_variance_scale
        # a floor under the prediction's variances keeps its inverse finite at the start
        cov = self.covariance + np.diag([1e-8, 1e-8, 1e-10, 0.0, 0.0])
        post = np.linalg.inv(np.linalg.inv(cov) + info)
        post = 0.5 * (post + post.T)
        z = np.zeros(5)
        z[:3] = np.array(result.pose) - np.array(prior)
        z[2] = math.remainder(z[2], 2 * math.pi)
        step = post @ info @ z
        pose = (prior[0] + step[0], prior[1] + step[1], prior[2] + step[2])
        if o.calibrate_odometry:
            self.calibration = (
                float(np.clip(self.calibration[0] + step[3], -0.5, 0.5)),
                float(np.clip(self.calibration[1] + step[4], -0.5, 0.5)),
            )
            self.covariance = post
        else:
            post[3:, :] = 0.0
            post[:, 3:] = 0.0
            self.covariance = post
        self._last = pose
        return MatchResult(pose, result.score, True, result.points)
