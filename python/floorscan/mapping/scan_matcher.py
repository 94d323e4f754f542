"""Correcting the odometry pose with the robot's own scans: a correlative scan-to-map matcher
(Olson 2009; cartographer's real-time correlative scan matcher, hector_mapping's role).
The drive loop (``floorscan drive``) and the pipeline's local scan matching (``floorscan run``,
``node``, ``fleet``, ``eval``: :mod:`floorscan.pipeline.pose_correction`) share it; its
options are the Rust ``ScanMatcherOptions`` (``[slam.matcher]`` in the config file).

The robot keeps a persistent map of where its scans ended (hit counts on a fixed grid centred
on its start, in the frame its waypoints are given in). Each frame, the scan's end points
(visual boundary points, or laser returns) are tried at every pose of a small window around
the odometry pose (translations on the grid's cells, yaws in fixed steps); each pose scores
the mean of a likelihood field (exp(-d^2 / 2 sigma^2), d the distance to the nearest hit in
the map) at the points, times a prior exp(-(|t| / sigma_t)^2 - (theta / sigma_theta)^2) that
keeps the pose near odometry where the scan does not decide (a corridor's length). The best
pose is kept when enough points score; then the scan's points that the map does not already
explain (no stored hit within ``novelty_m``) join the map at that pose. Storing only what is
new keeps the map as it was first seen: a robot that comes back with drifted odometry matches
the walls as they were, not its own latest, drifted copies of them (which would let the error
stay, as a matcher against its last few frames does).

The pose kept is not the best pose as it is: the match is fused with the odometry
prediction as an extended Kalman filter (``predict``, ``information``, ``fuse``). The
prediction's covariance grows with each wheel's travel; the match's information is the
curvature of the summed field values over (x, y, yaw) at the pose found, so a corridor
corrects across itself and not along, and a narrow view of near walls corrects the heading
little; two more states estimate odometry's systematic errors (turn scale, heading drift per
metre) from the matches, as robots calibrate their odometry, and correct each prediction.
Kept as it was, each frame's match (the best of a flat-topped score) scattered by about
0.015 rad, and the points stored at it turned that scatter into a rotated map of each
unseen room (EVALUATION.md, "Long tours").

Storing (the novelty test and the stamps into the cached field) runs in the Rust core
(``floorscan_core::hit_map``), in place on the numpy counts and field kept here, as do the
search (``floorscan_core::scan_matcher``) and the match's information matrix
(``floorscan_core::match_information``); the filter's 5 x 5 algebra is written out on floats.

Odometry's heading error grows with the square root of the distance travelled (wheel noise)
and turns it into metres of position error; matching against walls seen before keeps the
heading, and so the waypoints, where they are. It cannot close large loops (no global search,
no graph): what was never seen stays as odometry leaves it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Dict, Optional, Tuple

import numpy as np

from .._native.drive import HitMap, correlative_search, match_information
from ..options import check
from ..ranging.scan import ColumnStatus

CACHE_MARGIN_M = 1.0
"""The likelihood field is computed this much [m] beyond what one match needs, and reused
(new hits stamped into it) while the robot stays within it."""
STAMP_SIGMAS = 3.0
"""The field is 0 beyond this many sigmas from every hit (exp(-4.5) = 0.011)."""


def boundary_points_robot(scan, robot_from_camera) -> np.ndarray:
    """The scan's boundary points (N, 2) [m, robot frame]: the camera's ground frame moved by
    ``robot_from_camera`` (x [m], y [m], yaw [rad]). What the matcher matches and stores of a
    visual scan (its columns with no boundary, too close or invalid say nothing of walls)."""
    bnd = np.asarray(scan.status_codes) == int(ColumnStatus.BOUNDARY)  # an int compares fast
    x, y = np.asarray(scan.x)[bnd], np.asarray(scan.y)[bnd]
    m = robot_from_camera
    c, s = math.cos(m[2]), math.sin(m[2])
    return np.stack([m[0] + c * x - s * y, m[1] + s * x + c * y], 1)


def _disc(r: int, cell_m: float, radius_m: float):
    """Cell offsets (di, dj) within ``radius_m`` [m] of the centre cell, and their distances
    [m], for a square of half-side ``r`` cells."""
    d = np.arange(-r, r + 1)
    di, dj = (a.ravel() for a in np.meshgrid(d, d))
    dist = np.hypot(di, dj) * cell_m
    keep = dist <= radius_m + 1e-12
    return di[keep], dj[keep], dist[keep]


def _inverse3(a):
    """The inverse of the 3 x 3 matrix ``a`` (rows of floats), by its adjugate."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    c00, c01, c02 = a11 * a22 - a12 * a21, a12 * a20 - a10 * a22, a10 * a21 - a11 * a20
    inv_det = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    return [
        [c00 * inv_det, (a02 * a21 - a01 * a22) * inv_det, (a01 * a12 - a02 * a11) * inv_det],
        [c01 * inv_det, (a00 * a22 - a02 * a20) * inv_det, (a02 * a10 - a00 * a12) * inv_det],
        [c02 * inv_det, (a01 * a20 - a00 * a21) * inv_det, (a00 * a11 - a01 * a10) * inv_det],
    ]


class ScanMatcherOptions:
    """The matcher's options: the Rust ``ScanMatcherOptions`` (defaults, docs and rules live
    there, ``crates/floorscan-core/src/mapping/scan_matcher_options.rs``; ``floorscan.options.
    field_docs("scan_matcher")`` reads the docs). Keyword arguments are any of its fields;
    the others take their defaults; a bad one is an :class:`~floorscan.OptionError` naming
    it. Read-only, attribute access; ``replace(**changes)`` makes a changed copy.

    >>> ScanMatcherOptions(size_m=12.0).size_m, ScanMatcherOptions().min_points
    (12.0, 40)
    """

    __slots__ = ("_values",)

    def __init__(self, **options: Any) -> None:
        object.__setattr__(self, "_values", check("scan_matcher", options))

    @classmethod
    def from_dict(cls, values: Dict[str, Any]) -> ScanMatcherOptions:
        """The options of a dict of any of the fields (a config table's ``matcher``)."""
        return cls(**values)

    def __getattr__(self, name: str) -> Any:
        try:
            return object.__getattribute__(self, "_values")[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("ScanMatcherOptions is read-only: use replace(...)")

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ScanMatcherOptions) and self._values == other._values

    def __hash__(self) -> int:
        return hash(tuple(sorted(self._values.items())))

    def __repr__(self) -> str:
        return f"ScanMatcherOptions({self._values!r})"

    def to_dict(self) -> Dict[str, Any]:
        """Every field (the serde form)."""
        return dict(self._values)

    def replace(self, **changes: Any) -> ScanMatcherOptions:
        return ScanMatcherOptions(**{**self._values, **changes})

    @property
    def gate(self) -> float:
        """``rejection_threshold``, inf when unset (no gate)."""
        g = self._values["rejection_threshold"]
        return math.inf if g is None else float(g)


@dataclass(frozen=True)
class MatchResult:
    """``pose``: the corrected world_from_robot (x, y, yaw); ``score``: its mean field value;
    ``accepted``: whether the correction was applied; ``points``: points used."""

    pose: Tuple[float, float, float]
    score: float
    accepted: bool
    points: int


class ScanMatcher:
    """The persistent hit map and the correlative search (see the module's docstring)."""

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
        r = int(math.floor(options.novelty_m / self.cell))
        novelty = _disc(r, self.cell, r * self.cell)[:2] if r > 0 else (np.zeros(0, int),) * 2
        self._native = HitMap(
            self.n,
            self.cell,
            self.origin_m,
            options.range_max_m,
            np.ascontiguousarray(np.stack(novelty, 1), np.int64),
            np.ascontiguousarray(np.stack([di, dj], 1), np.int64),
            self._stamp_values,
        )
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
        """The covariance (5, 5) of the state's error: x [m], y [m], yaw [rad], the turn scale
        error, the heading drift [rad/m]."""
        return np.array(self._covariance)

    @covariance.setter
    def covariance(self, value) -> None:
        self._covariance = np.asarray(value, np.float64).reshape(5, 5).tolist()

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

    def insert(self, points_robot: np.ndarray, pose, *, novel_only: bool = False) -> int:
        """Adds the points [m, robot frame] seen from ``pose`` to the map (counts saturate
        at 255); ``novel_only``: only those without a stored hit within ``novelty_m``.
        Returns how many were stored."""
        pts = np.ascontiguousarray(points_robot, np.float64).reshape(-1, 2)
        field, i0, j0 = self._cache if self._cache is not None else (None, 0, 0)
        stored = self._native.insert(
            self.hits,
            pts,
            tuple(float(v) for v in pose[:3]),
            novel_only and self.frames > 0,
            field,
            (i0, j0),
        )
        if stored and field is not None:
            self._cache_nonzero = self._cache_nonzero or bool(field.any())
        self.frames += 1
        return stored

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
        # the covariance grows as F P F^T + G M G^T: F = I + E, E the pose's dependence on the
        # heading and on the calibration (rows 0-2), G M G^T the wheels' noise (M over the
        # distance and the turn) turned into x, y, yaw; written out on floats (a few
        # microseconds; numpy's calls on 5 x 5 arrays took three times as long)
        b = o.odometry_wheelbase_m
        vl = o.odometry_wheel_sigma**2 * abs(d - 0.5 * b * dth)
        vr = o.odometry_wheel_sigma**2 * abs(d + 0.5 * b * dth)
        m00, m01, m11 = 0.25 * (vl + vr), 0.5 * (vr - vl) / b, (vl + vr) / b**2
        h = a[2] + 0.5 * (dth + extra)
        ch, sh = math.cos(h), math.sin(h)
        e02, e03, e04 = -wy, -wy * 0.5 * dth, -wy * 0.5 * d
        e12, e13, e14 = wx, wx * 0.5 * dth, wx * 0.5 * d
        e23, e24 = dth, d
        p0, p1, p2, p3, p4 = self._covariance
        fp = (  # F P
            [p0[c] + e02 * p2[c] + e03 * p3[c] + e04 * p4[c] for c in range(5)],
            [p1[c] + e12 * p2[c] + e13 * p3[c] + e14 * p4[c] for c in range(5)],
            [p2[c] + e23 * p3[c] + e24 * p4[c] for c in range(5)],
            p3,
            p4,
        )
        cov = [  # (F P) F^T
            [
                r[0] + e02 * r[2] + e03 * r[3] + e04 * r[4],
                r[1] + e12 * r[2] + e13 * r[3] + e14 * r[4],
                r[2] + e23 * r[3] + e24 * r[4],
                r[3],
                r[4],
            ]
            for r in fp
        ]
        q00, q01, q11 = ch * m00 * ch, ch * m00 * sh, sh * m00 * sh
        q02, q12 = ch * m01, sh * m01
        cov[0][0] += q00
        cov[0][1] += q01
        cov[1][0] += q01
        cov[1][1] += q11
        cov[0][2] += q02
        cov[2][0] += q02
        cov[1][2] += q12
        cov[2][1] += q12
        cov[2][2] += m11
        cov[3][3] += o.calibration_drift**2 * abs(dth)
        cov[4][4] += o.calibration_drift**2 * abs(d)
        self._covariance = cov
        self._last = pred
        return pred

    def information(self, points_robot: np.ndarray, pose) -> np.ndarray:
        """The information matrix (3, 3) of the scan's match at ``pose``: minus the Hessian of
        the sum of field values (read bilinearly as the search reads them) at the points over
        (x, y, yaw), by central differences of a cell and a yaw step, with its negative
        eigenvalues cut to 0. Each point on a wall adds 1 / sigma_m^2 across it. A point whose
        four cells leave the cached field reads 0 (the field covers the search window with a
        margin: none do in a drive). Computed in the Rust core
        (``floorscan_core::match_information``)."""
        if self._cache is None:
            return np.zeros((3, 3))
        field, i0, j0 = self._cache
        origin = (self.origin_m[0] + i0 * self.cell, self.origin_m[1] + j0 * self.cell)
        return match_information(
            np.ascontiguousarray(field),
            origin,
            self.cell,
            self._matched_points(points_robot),
            tuple(float(v) for v in pose[:3]),
            self.options.yaw_step_rad,
        )

    def fuse(self, result: MatchResult, prior, information: np.ndarray) -> MatchResult:
        """The accepted match fused with the prediction ``prior`` (``predict`` first) in
        information form: the match's information is ``information`` /
        ``match_variance_scale``; the covariance shrinks accordingly."""
        o = self.options
        prior = tuple(float(v) for v in prior[:3])
        if not result.accepted or o.match_variance_scale == 0:
            self._last = tuple(result.pose)
            return result
        # post = (P^-1 + J)^-1 = (I + P J)^-1 P with J the match's information in the pose's
        # 3 x 3 block: I + P J = [[A, 0], [P21 J, I]], A = I + P11 J (its eigenvalues those of
        # I plus a product of two positive semi-definite matrices: >= 1), so only A is inverted
        scale = o.match_variance_scale
        j = [[v / scale for v in row] for row in np.asarray(information, np.float64).tolist()]
        # a floor under the prediction's variances keeps it positive definite at the start
        p = [row[:] for row in self._covariance]
        p[0][0] += 1e-8
        p[1][1] += 1e-8
        p[2][2] += 1e-10
        j0, j1, j2 = j
        pj = [[r[0] * j0[c] + r[1] * j1[c] + r[2] * j2[c] for c in range(3)] for r in p]
        ainv = _inverse3(
            [[pj[r][c] + (1.0 if r == c else 0.0) for c in range(3)] for r in range(3)]
        )
        p0, p1, p2 = p[0], p[1], p[2]
        post = [[a[0] * p0[c] + a[1] * p1[c] + a[2] * p2[c] for c in range(5)] for a in ainv]
        t0, t1, t2 = post
        for r in (3, 4):
            pr, q = p[r], pj[r]
            post.append([pr[c] - (q[0] * t0[c] + q[1] * t1[c] + q[2] * t2[c]) for c in range(5)])
        post = [[0.5 * (post[r][c] + post[c][r]) for c in range(5)] for r in range(5)]
        z = (
            result.pose[0] - prior[0],
            result.pose[1] - prior[1],
            math.remainder(result.pose[2] - prior[2], 2 * math.pi),
        )
        u = [r[0] * z[0] + r[1] * z[1] + r[2] * z[2] for r in j]
        # the innovation's squared Mahalanobis distance z^T (P + J^-1)^-1 z, written
        # z^T J (I + P J)^-1 z so that a J without full rank (a corridor) needs no inverse
        w = [a[0] * z[0] + a[1] * z[1] + a[2] * z[2] for a in ainv]
        self.last_mahalanobis = math.sqrt(
            max(0.0, sum(z[r] * sum(j[r][c] * w[c] for c in range(3)) for r in range(3)))
        )
        if self.last_mahalanobis > o.gate:
            self._last = prior
            return MatchResult(prior, result.score, False, result.points)
        step = [r[0] * u[0] + r[1] * u[1] + r[2] * u[2] for r in post]
        pose = (prior[0] + step[0], prior[1] + step[1], prior[2] + step[2])
        if o.calibrate_odometry:
            self.calibration = (
                min(max(self.calibration[0] + step[3], -0.5), 0.5),
                min(max(self.calibration[1] + step[4], -0.5), 0.5),
            )
        else:
            for r in range(5):
                for c in range(5):
                    if r >= 3 or c >= 3:
                        post[r][c] = 0.0
        self._covariance = post
        self._last = pose
        return MatchResult(pose, result.score, True, result.points)

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
