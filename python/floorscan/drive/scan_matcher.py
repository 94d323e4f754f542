"""Correcting the odometry pose with the robot's own scans: a correlative scan-to-map matcher
(Olson 2009; cartographer's real-time correlative scan matcher, hector_mapping's role).

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

Storing (the novelty test and the stamps into the cached field) runs in the Rust core
(``floorscan_core::hit_map``), in place on the numpy counts and field kept here, as does the
search (``floorscan_core::scan_matcher``).

Odometry's heading error grows with the square root of the distance travelled (wheel noise)
and turns it into metres of position error; matching against walls seen before keeps the
heading, and so the waypoints, where they are. It cannot close large loops (no global search,
no graph): what was never seen stays as odometry leaves it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from .._native.drive import HitMap, correlative_search
from ..errors import OptionError

CACHE_MARGIN_M = 1.0
"""The likelihood field is computed this much [m] beyond what one match needs, and reused
(new hits stamped into it) while the robot stays within it."""
STAMP_SIGMAS = 3.0
"""The field is 0 beyond this many sigmas from every hit (exp(-4.5) = 0.011)."""


def _disc(r: int, cell_m: float, radius_m: float):
    """Cell offsets (di, dj) within ``radius_m`` [m] of the centre cell, and their distances
    [m], for a square of half-side ``r`` cells."""
    d = np.arange(-r, r + 1)
    di, dj = (a.ravel() for a in np.meshgrid(d, d))
    dist = np.hypot(di, dj) * cell_m
    keep = dist <= radius_m + 1e-12
    return di[keep], dj[keep], dist[keep]


@dataclass(frozen=True)
class ScanMatcherOptions:
    """- ``size_m``: side of the persistent map [m], centred on the start, in [4, 400].
      Default 80 (a floor of a building; 10 MB at the default cell). Points outside it are
      neither matched nor stored.
    - ``cell_size_m``: [m/cell], in [0.01, 0.2]. Default 0.025 (half the avoidance map's).
    - ``sigma_m``: width of the likelihood field [m], > 0. Default 0.05 (the camera's
      boundary error within 2 m; EVALUATION.md).
    - ``search_xy_m``, ``search_yaw_rad``: half-widths of the search window. Defaults 0.15 m
      and 0.15 rad (odometry's heading error over a room's excursion: the wheelbase error alone
      is 0.06 rad per half turn).
    - ``yaw_step_rad``: default 0.01 (2.5 cm at 2.5 m, one cell).
    - ``prior_xy_m``, ``prior_yaw_rad``: widths of the odometry prior. Defaults 0.3 m and
      0.3 rad (weak: a wall seen before wins, a featureless view keeps odometry).
    - ``min_points``: fewest scan points to match, >= 3. Default 15.
    - ``min_score``: the best pose's mean field value needed to accept it, in (0, 1).
      Default 0.35 (about half the points within 7 cm of a stored hit).
    - ``range_max_m``: points farther than this are ignored [m]. Default 3.0 (the ranger's
      range; boundaries beyond it are a footprint of a pixel row apart).
    - ``max_points``: at most this many points, evenly spaced along the scan, are matched
      (>= ``min_points``), a bound on the work of one match. Default 400 (more than a
      640-wide image's 320 columns give; 100 of a laser's 271 beams measured worse: 0.27 m
      against 0.10 m largest pose error on the corridor test drive).
    - ``novelty_m``: a scan point joins the map only when no stored hit lies within this
      distance [m] of it, in [0, 1]; 0 stores every point. Default 0.1 (2 sigma).
    """

    size_m: float = 80.0
    cell_size_m: float = 0.025
    sigma_m: float = 0.05
    search_xy_m: float = 0.15
    search_yaw_rad: float = 0.15
    yaw_step_rad: float = 0.01
    prior_xy_m: float = 0.3
    prior_yaw_rad: float = 0.3
    min_points: int = 15
    min_score: float = 0.35
    range_max_m: float = 3.0
    novelty_m: float = 0.1
    max_points: int = 400

    def __post_init__(self) -> None:
        checks = {
            "size_m": 4.0 <= self.size_m <= 400.0,
            "cell_size_m": 0.01 <= self.cell_size_m <= 0.2,
            "sigma_m": 0 < self.sigma_m <= 1.0,
            "search_xy_m": 0 <= self.search_xy_m <= 2.0,
            "search_yaw_rad": 0 <= self.search_yaw_rad <= 0.5,
            "yaw_step_rad": 0.001 <= self.yaw_step_rad <= 0.1,
            "prior_xy_m": self.prior_xy_m > 0,
            "prior_yaw_rad": self.prior_yaw_rad > 0,
            "min_points": int(self.min_points) >= 3,
            "min_score": 0 < self.min_score < 1,
            "range_max_m": 0 < self.range_max_m <= 100,
            "novelty_m": 0 <= self.novelty_m <= 1,
            "max_points": int(self.min_points) <= int(self.max_points) <= 100_000,
        }
        for name, ok in checks.items():
            if not (ok and math.isfinite(float(getattr(self, name)))):
                raise OptionError(f"invalid option `{name}`: got {getattr(self, name)!r}")
        if (self.size_m / self.cell_size_m) ** 2 > 64e6:
            raise OptionError("invalid options: size_m / cell_size_m gives over 64 M cells")


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

    def __init__(
        self, options: ScanMatcherOptions = ScanMatcherOptions(), *, center=(0.0, 0.0)
    ) -> None:
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
        self._cache_nonzero = False

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
        pts = self._usable(points_robot)
        if len(pts) < o.min_points or self.frames == 0:
            return MatchResult(prior, 0.0, False, len(pts))
        if len(pts) > o.max_points:
            pts = pts[np.linspace(0, len(pts) - 1, int(o.max_points)).round().astype(np.int64)]
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

    def correct(self, points_robot: np.ndarray, prior) -> MatchResult:
        """Matches the scan near ``prior``, then stores what it shows that the map does not
        hold yet, at the pose found (or at the prior when the match is refused)."""
        result = self.match(points_robot, prior)
        self.insert(points_robot, result.pose, novel_only=True)
        return result
