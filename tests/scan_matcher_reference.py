"""floorscan's correlative scan matcher as first written in Python (numpy, OpenCV's exact
distance transform), before its state and steps moved into the Rust core
(``floorscan_core::scan_matcher``): the reference the core must equal, step by step and over whole
runs (tests/mapping/test_scan_matcher_native.py, tests/mapping/test_scan_matcher_filter.py)."""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np
from floorscan._native.mapping import correlative_search
from floorscan.mapping.scan_matcher import MatchResult, ScanMatcherOptions

CACHE_MARGIN_M = 1.0
STAMP_SIGMAS = 3.0


def _disc(r: int, cell_m: float, radius_m: float):
    """Cell offsets (di, dj) within ``radius_m`` [m] of the centre cell, and their distances
    [m], for a square of half-side ``r`` cells."""
    d = np.arange(-r, r + 1)
    di, dj = (a.ravel() for a in np.meshgrid(d, d))
    dist = np.hypot(di, dj) * cell_m
    keep = dist <= radius_m + 1e-12
    return di[keep], dj[keep], dist[keep]


class ReferenceScanMatcher:
    """floorscan's scan matcher as first written in Python: numpy and OpenCV's exact distance
    transform for the field, numpy for storing and for the filter; the search is the core's
    (``correlative_search``, tested against brute force in the core)."""

    def __init__(self, options: Optional[ScanMatcherOptions] = None, *, center=(0.0, 0.0)) -> None:
        options = options if options is not None else ScanMatcherOptions()
        self.options = options
        self.cell = options.cell_size_m
        self.n = int(math.ceil(options.size_m / self.cell))
        self.origin_m = (
            float(center[0]) - 0.5 * self.n * self.cell,
            float(center[1]) - 0.5 * self.n * self.cell,
        )
        self.hits = np.zeros((self.n, self.n), np.uint8)
        self.frames = 0
        # cell offsets (di, dj) of the field's Gaussian stamp and their values; of the
        # novelty disc: fixed by the options, made once
        r = int(math.floor(STAMP_SIGMAS * options.sigma_m / self.cell))
        di, dj, dist = _disc(r, self.cell, STAMP_SIGMAS * options.sigma_m)
        self._stamp_values = np.exp(-0.5 * (dist / options.sigma_m) ** 2).astype(np.float32)
        self._stamp_offsets = (di, dj)
        r = int(math.floor(options.novelty_m / self.cell))
        self._novelty_offsets = _disc(r, self.cell, r * self.cell)[:2] if r > 0 else None
        # the last likelihood field (field, i0, j0), reused while the robot stays within it;
        # newly stored hits are stamped into it; whether it holds any non-zero value
        self._cache: Optional[Tuple[np.ndarray, int, int]] = None
        # the last fused match's innovation as a Mahalanobis distance (None before any)
        self.last_mahalanobis: Optional[float] = None
        self._cache_nonzero = False
        # the pose kept last and the covariance of its error (x [m], y [m], yaw [rad])
        self._last: Optional[Tuple[float, float, float]] = None
        # state: the pose and odometry's estimated errors (turn scale error, heading drift
        # per metre); the covariance of its error
        self.calibration = (0.0, 0.0)
        self._covariance = [[0.0] * 5 for _ in range(5)]  # rows of floats (see `covariance`)
        if options.calibrate_odometry:
            self._covariance[3][3] = options.turn_error_prior**2
            self._covariance[4][4] = options.drift_prior_rad_per_m**2
        self._origin = (0.0, 0.0)  # of the field the last match used

    @property
    def covariance(self) -> np.ndarray:
        return np.array(self._covariance)

    @covariance.setter
    def covariance(self, value) -> None:
        self._covariance = np.asarray(value, np.float64).reshape(5, 5).tolist()

    @property
    def last_pose(self):
        return self._last

    @last_pose.setter
    def last_pose(self, value) -> None:
        self._last = None if value is None else tuple(float(v) for v in value)

    def _window(self, x0: float, y0: float, half_m: float) -> Tuple[int, int, int, int]:
        """Cells (i0, j0, i1, j1), end exclusive, of the square of half-side ``half_m``
        [m] around (x0, y0), cut to the map."""
        ci = math.floor((x0 - self.origin_m[0]) / self.cell)
        cj = math.floor((y0 - self.origin_m[1]) / self.cell)
        r = int(math.ceil(half_m / self.cell))
        return (
            max(0, int(ci) - r),
            max(0, int(cj) - r),
            min(self.n, int(ci) + r + 1),
            min(self.n, int(cj) + r + 1),
        )

    def _usable(self, points_robot: np.ndarray) -> np.ndarray:
        """The finite points (N, 2) within ``range_max_m``."""
        pts = np.asarray(points_robot, np.float64).reshape(-1, 2)
        # a non-finite coordinate makes the distance NaN or inf: one test drops both
        return pts[np.hypot(pts[:, 0], pts[:, 1]) <= self.options.range_max_m]

    def _matched_points(self, points_robot: np.ndarray) -> np.ndarray:
        """The usable points (N, 2), at most ``max_points`` of them evenly spaced along the
        scan: the points a match reads."""
        pts = self._usable(points_robot)
        if len(pts) > self.options.max_points:
            idx = np.linspace(0, len(pts) - 1, int(self.options.max_points)).round()
            pts = pts[idx.astype(np.int64)]
        return np.ascontiguousarray(pts)

    def _field(self, x0: float, y0: float, half_m: float):
        """The likelihood field over a square of half-side ``half_m`` around (x0, y0):
        (field (h, w) float32, i0, j0) with i0, j0 the crop's first cell."""
        import cv2

        i0, j0, i1, j1 = self._window(x0, y0, half_m)
        if i1 <= i0 or j1 <= j0:
            return np.zeros((0, 0), np.float32), i0, j0
        crop = self.hits[j0:j1, i0:i1]
        if not crop.any():
            return np.zeros(crop.shape, np.float32), i0, j0
        free = np.where(crop > 0, 0, 255).astype(np.uint8)
        d = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * self.cell
        s = self.options.sigma_m
        field = np.exp(-0.5 * (d / s) ** 2).astype(np.float32)
        field[d > STAMP_SIGMAS * s] = 0.0
        return field, i0, j0

    def _cached_field(self, x0: float, y0: float, half_m: float):
        """The field over at least ``half_m`` around (x0, y0): the cached one when it covers
        that square, else a new one ``CACHE_MARGIN_M`` larger."""
        if self._cache is not None:
            field, i0, j0 = self._cache
            h, w = field.shape
            lo_i, lo_j, hi_i, hi_j = self._window(x0, y0, half_m)
            if i0 <= lo_i and j0 <= lo_j and hi_i <= i0 + w and hi_j <= j0 + h:
                return self._cache
        self._cache = self._field(x0, y0, half_m + CACHE_MARGIN_M)
        self._cache_nonzero = bool(self._cache[0].any())
        return self._cache

    def match(self, points_robot: np.ndarray, prior) -> MatchResult:
        """The best pose for ``points_robot`` (N, 2) [m, robot frame] near ``prior``
        (world_from_robot); does not change the map."""
        o = self.options
        prior = tuple(float(v) for v in prior)
        pts = self._matched_points(points_robot)
        if len(pts) < o.min_points or self.frames == 0:
            return MatchResult(prior, 0.0, False, len(pts))
        half = o.range_max_m + o.search_xy_m + 3 * o.sigma_m
        field, i0, j0 = self._cached_field(prior[0], prior[1], half)
        if field.size == 0 or not self._cache_nonzero:
            return MatchResult(prior, 0.0, False, len(pts))
        origin = (self.origin_m[0] + i0 * self.cell, self.origin_m[1] + j0 * self.cell)
        pose, mean, _ = correlative_search(
            np.ascontiguousarray(field),
            origin,
            self.cell,
            np.ascontiguousarray(pts),
            prior,
            int(round(o.search_xy_m / self.cell)),
            int(round(o.search_yaw_rad / o.yaw_step_rad)),
            o.yaw_step_rad,
            o.prior_xy_m,
            o.prior_yaw_rad,
        )
        pose = tuple(float(v) for v in pose)
        if mean < o.min_score:
            return MatchResult(prior, mean, False, len(pts))
        return MatchResult(pose, mean, True, len(pts))

    def correct(self, points_robot: np.ndarray, prior) -> MatchResult:
        """Matches the scan near ``prior``, fuses the match with it (``fuse``), then stores
        what the scan shows that the map does not hold yet, at the pose kept (the prior when
        the match is refused)."""
        prior = self.predict(prior)
        result = self.match(points_robot, prior)
        if result.accepted and self.options.match_variance_scale > 0:
            result = self.fuse(result, prior, self.information(points_robot, result.pose))
        else:
            result = self.fuse(result, prior, np.zeros((3, 3)))
        self.insert(points_robot, result.pose, novel_only=True)
        return result

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
