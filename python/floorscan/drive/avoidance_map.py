"""The map the robot avoids obstacles with: a square log-odds window in the odometry frame that
scrolls with the robot, fed visual scans through the calibrated
:class:`~floorscan.drive.VisualSensorModel` (or an ideal laser), and forgetting stale evidence
so obstacles that moved away clear.

Cells between adjacent columns count as seen: each pair of neighbouring readings fills the
floor quadrilateral between their near edges of view and their ends, so one frame covers the
whole view (a scan of single rays leaves most far cells untouched and needs many frames).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np

from ..errors import OptionError
from ..mapping.grid_views import GridExtent
from ..options import defaults
from ..ranging.scan import ColumnStatus
from .sensor_model import VisualSensorModel

_SHIFT = 4  # sub-cell precision of rasterised polygons: 1 / 16 cell
_NO_EVIDENCE = 0.05  # |log odds| below this: no evidence (unknown), whatever the calibration


@dataclass(frozen=True)
class AvoidanceMapOptions:
    """- ``size_m``: side of the window [m], in [1, 100]. Default 8 (room for a plan around
      an obstacle ahead of the paper's 3 m camera range in every direction).
    - ``cell_size_m``: [m/cell], in [0.01, 0.5]. Default 0.05 (the ROS navigation stack's
      local costmap resolution).
    - ``clamp_nats``: (min, max) log odds, min < 0 < max. Default (-2.0, 3.5), the local
      map's clamps (OctoMap's 0.12 / 0.97): a cell seen free a few times still turns
      occupied within two frames when an obstacle appears (wider clamps made the closed
      loop hesitate). The output calibration maps the clamped values to probabilities.
    - ``half_life_s``: evidence halves every this many seconds without new readings
      (forgetting), > 0 or None (never). Default 3 s: long enough to remember an obstacle
      that left the camera's view while the robot turns past it, short enough that a moved
      obstacle the camera no longer sees fades within a corridor's length.
    - ``occupied_threshold``, ``free_threshold``: class thresholds on the probability.
      Defaults: the occupancy grid's (``GridOptions``, map_server's thresholds).
    - ``probability_scale``, ``probability_offset``: the map's probability of a cell is
      logistic(scale * log_odds + offset), a Platt calibration of the fused evidence
      (successive frames are correlated, so summed evidence overstates certainty). Defaults
      0.612 / -1.581, fitted by ``bench/drive_sensor_model.py`` on the corridor and room
      (EVALUATION.md); (1, 0) reads the log odds as they are (the laser robot).
    - ``probability_knots``: instead of the Platt curve, a monotone calibration: knots
      ((log_odds, probability), ...) with increasing log odds and non-decreasing
      probabilities in [0, 1], interpolated linearly (constant beyond the ends); fitted by
      isotonic regression (:func:`~floorscan.drive.sensor_fit.fit_probability_knots`).
      Default None (Platt).
    """

    size_m: float = 8.0
    cell_size_m: float = 0.05
    clamp_nats: Tuple[float, float] = (-2.0, 3.5)
    half_life_s: Optional[float] = 3.0
    occupied_threshold: float = field(
        default_factory=lambda: defaults("grid")["occupied_threshold"]
    )
    free_threshold: float = field(default_factory=lambda: defaults("grid")["free_threshold"])
    probability_scale: float = 0.612
    probability_offset: float = -1.581
    probability_knots: Optional[Tuple[Tuple[float, float], ...]] = None

    def __post_init__(self) -> None:
        if not 1.0 <= self.size_m <= 100.0:
            raise OptionError(f"invalid option `size_m`: must be in [1, 100], got {self.size_m}")
        if not 0.01 <= self.cell_size_m <= 0.5:
            raise OptionError(
                f"invalid option `cell_size_m`: must be in [0.01, 0.5], got {self.cell_size_m}"
            )
        lo, hi = self.clamp_nats
        if not lo < 0 < hi:
            raise OptionError(f"invalid option `clamp_nats`: need min < 0 < max, got {lo, hi}")
        if self.half_life_s is not None and not self.half_life_s > 0:
            raise OptionError(f"invalid option `half_life_s`: must be > 0, got {self.half_life_s}")
        if not (0 < self.probability_scale <= 10 and abs(self.probability_offset) <= 10):
            raise OptionError(
                "invalid probability calibration: need 0 < scale <= 10, |offset| <= 10"
            )
        if self.probability_knots is not None:
            k = np.asarray(self.probability_knots, np.float64)
            ok = k.ndim == 2 and k.shape[1] == 2 and 2 <= len(k) <= 1000
            ok = ok and bool(np.all(np.isfinite(k))) and bool(np.all(np.diff(k[:, 0]) > 0))
            ok = (
                ok
                and bool(np.all(np.diff(k[:, 1]) >= 0))
                and bool(np.all((k[:, 1] >= 0) & (k[:, 1] <= 1)))
            )
            if not ok:
                raise OptionError(
                    "invalid option `probability_knots`: need 2-1000 (log_odds, probability) "
                    "pairs, log odds increasing, probabilities non-decreasing in [0, 1]"
                )
        if not 0 < self.free_threshold < 0.5 < self.occupied_threshold < 1:
            raise OptionError("invalid thresholds: need 0 < free < 0.5 < occupied < 1")


def _stamp_hits(hit, cx, cy, rad, values, ok, near) -> None:
    """Draws into ``hit`` (n, n) the discs of radius ``rad`` [cells] around the boundary
    points (cx, cy) [fractional cells: cell k spans [k, k + 1)] where ``ok``, each with its
    ``values`` entry (the cells whose centre lies within the radius), and the segments from
    point k to k + 1 where ``near[k]`` (the obstacle's face between adjacent columns) with the
    smaller of the two values (the cells the segment passes through, sampled every half
    cell). All readings at once: one OpenCV call per reading cost more than the rest of an
    insertion."""
    n_rows, n_cols = hit.shape
    idx = np.nonzero(ok)[0]
    if idx.size:
        x, y, r, v = cx[idx], cy[idx], rad[idx], values[idx]
        m = int(np.ceil(r.max())) + 1
        d = np.arange(-m, m + 1)
        di, dj = (a.ravel() for a in np.meshgrid(d, d))
        pi = np.floor(x)[:, None] + di[None, :]
        pj = np.floor(y)[:, None] + dj[None, :]
        inside = (pi + 0.5 - x[:, None]) ** 2 + (pj + 0.5 - y[:, None]) ** 2 <= (r * r)[:, None]
        inside &= (pi >= 0) & (pi < n_cols) & (pj >= 0) & (pj < n_rows)
        vals = np.broadcast_to(v[:, None], pi.shape)
        hit[pj[inside].astype(np.int64), pi[inside].astype(np.int64)] = vals[inside]
    seg = np.nonzero(near)[0]
    if seg.size:
        x0, y0, x1, y1 = cx[seg], cy[seg], cx[seg + 1], cy[seg + 1]
        steps = int(np.ceil(2 * np.hypot(x1 - x0, y1 - y0).max())) + 2
        t = np.linspace(0.0, 1.0, steps)[None, :]
        pi = np.floor(x0[:, None] + t * (x1 - x0)[:, None])
        pj = np.floor(y0[:, None] + t * (y1 - y0)[:, None])
        inside = (pi >= 0) & (pi < n_cols) & (pj >= 0) & (pj < n_rows)
        v = np.minimum(values[seg], values[seg + 1])
        vals = np.broadcast_to(v[:, None], pi.shape)
        hit[pj[inside].astype(np.int64), pi[inside].astype(np.int64)] = vals[inside]


def _logit(p: float) -> float:
    return math.log(p / (1.0 - p))


def _compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


class AvoidanceMap:
    """A scrolling log-odds window (odometry frame, REP 103; row 0 = lowest y)."""

    def __init__(self, options: AvoidanceMapOptions = AvoidanceMapOptions(), *, center=(0, 0)):
        self.options = options
        self.cell = options.cell_size_m
        self.n = int(round(options.size_m / self.cell))
        self.log_odds = np.zeros((self.n, self.n), np.float32)
        self.bumps = np.zeros((self.n, self.n), np.float32)
        self.x_cell = 0
        self.y_cell = 0
        self.recenter(*center[:2])
        self._plan_occ = _logit(options.occupied_threshold)
        self._plan_free = _logit(options.free_threshold)

    # --- geometry -------------------------------------------------------------------------
    @property
    def origin_m(self) -> Tuple[float, float]:
        return (self.x_cell * self.cell, self.y_cell * self.cell)

    @property
    def extent(self) -> GridExtent:
        return GridExtent(self.x_cell, self.y_cell, self.n, self.n, self.cell, self.origin_m)

    def recenter(self, x: float, y: float) -> None:
        """Scrolls by whole cells so (x, y) [m] lies within a quarter window of the centre;
        cells that enter are unknown."""
        half = self.n // 2
        cx, cy = int(math.floor(x / self.cell)) - half, int(math.floor(y / self.cell)) - half
        if abs(cx - self.x_cell) <= self.n // 4 and abs(cy - self.y_cell) <= self.n // 4:
            return
        dx, dy = cx - self.x_cell, cy - self.y_cell
        n = self.n
        layers = []
        for layer in (self.log_odds, self.bumps):
            out = np.zeros_like(layer)
            if abs(dx) < n and abs(dy) < n:
                src = layer[max(dy, 0) : n + min(dy, 0), max(dx, 0) : n + min(dx, 0)]
                out[max(-dy, 0) : n + min(-dy, 0), max(-dx, 0) : n + min(-dx, 0)] = src
            layers.append(out)
        self.log_odds, self.bumps = layers
        self.x_cell, self.y_cell = cx, cy

    def to_cells(self, x, y):
        """World (odometry frame) points [m] to fractional cell coordinates (col, row)."""
        return (np.asarray(x) / self.cell - self.x_cell, np.asarray(y) / self.cell - self.y_cell)

    # --- views ----------------------------------------------------------------------------
    def probabilities(self) -> np.ndarray:
        """Calibrated occupancy probabilities (see ``probability_scale``); cells without
        evidence read logistic(offset)."""
        a, b = self.options.probability_scale, self.options.probability_offset
        L = self.log_odds.astype(np.float64)
        knots = self.options.probability_knots
        if knots is not None:
            k = np.asarray(knots, np.float64)
            p = np.interp(L, k[:, 0], k[:, 1])
        else:
            p = 1.0 / (1.0 + np.exp(-(a * L + b)))
        p[np.abs(self.log_odds) < _NO_EVIDENCE] = 0.5
        return p

    def occupancy_classes(self) -> np.ndarray:
        """(H, W) uint8: 0 free, 1 unknown, 2 occupied: the planner's decisions, from the raw
        evidence against logit(free_threshold) / logit(occupied_threshold) (the calibrated
        probabilities of :meth:`probabilities` say how often such a decision is right; a
        single calibrated reading never reaches 0.65, and the map must still show it)."""
        c = np.ones(self.log_odds.shape, np.uint8)
        evidence = np.abs(self.log_odds) >= _NO_EVIDENCE
        c[(self.log_odds < self._plan_free) & evidence] = 0
        c[self.occupied()] = 2
        return c

    def occupied(self) -> np.ndarray:
        """The planner's obstacles: raw evidence above logit(occupied_threshold), before the
        output calibration (one confident reading suffices: for avoidance a missed obstacle
        costs more than a detour)."""
        return (self.log_odds > self._plan_occ) | (self.bumps > 0.5)

    # --- updates --------------------------------------------------------------------------
    def decay(self, dt_s: float) -> None:
        """Forgets: all evidence shrinks by 2^(-dt / half_life)."""
        hl = self.options.half_life_s
        if hl is not None and dt_s > 0:
            self.log_odds *= np.float32(0.5 ** (dt_s / hl))
            self.bumps *= np.float32(0.5 ** (dt_s / (10 * hl)))

    def _apply(self, free_mask, free_nats, hit_nats) -> None:
        lo, hi = self.options.clamp_nats
        L = self.log_odds
        sel = (free_mask > 0) & ~np.isfinite(hit_nats) if hit_nats is not None else free_mask > 0
        L[sel] += free_nats[sel]
        if hit_nats is not None:
            h = np.isfinite(hit_nats)
            L[h] += hit_nats[h]
        np.clip(L, lo, hi, out=L)

    def _fan(self, near_c, end_c, valid, cam_c) -> np.ndarray:
        """Mask of the quadrilaterals between neighbouring valid readings (cell coordinates).
        Each quadrilateral ends at the nearer of its two readings on both rays, so the floor
        seen past an obstacle's corner by one ray never clears the corner's cells."""
        mask = np.zeros(self.log_odds.shape, np.uint8)
        k = np.nonzero(valid[:-1] & valid[1:])[0]
        if k.size:
            cam = np.asarray(cam_c, np.float64)[None, :]
            d0, d1 = end_c[k] - cam, end_c[k + 1] - cam
            r0, r1 = np.hypot(*d0.T), np.hypot(*d1.T)
            r = np.minimum(r0, r1)
            e0 = cam + d0 * (r / np.maximum(r0, 1e-9))[:, None]
            e1 = cam + d1 * (r / np.maximum(r1, 1e-9))[:, None]
            quads = np.stack([near_c[k], near_c[k + 1], e1, e0], axis=1)
            # OpenCV's pixel p is centred on p; cell p spans [p, p + 1): half a cell back
            pts = np.round((quads - 0.5) * (1 << _SHIFT)).astype(np.int32)
            import cv2

            cv2.fillPoly(mask, list(pts), 1, lineType=cv2.LINE_8, shift=_SHIFT)
        return mask

    def _range_image(self, mask, cam_c) -> np.ndarray:
        jj, ii = np.nonzero(mask)
        r = np.full(mask.shape, np.nan, np.float32)
        r[jj, ii] = np.hypot(ii + 0.5 - cam_c[0], jj + 0.5 - cam_c[1]) * self.cell
        return r

    def insert_visual(
        self,
        scan,
        pose,
        *,
        mount=(0.0, 0.0, 0.0),
        table=None,
        model: Optional[VisualSensorModel] = None,
    ) -> None:
        """Adds one visual :class:`~floorscan.Scan` seen from ``pose`` (world_from_robot in
        the odometry frame), the camera at ``mount`` (robot_from_camera), with the evidence of
        ``model``; ``table`` (the ranger's :class:`~floorscan.GroundTable`) gives the predicted
        errors."""
        model = VisualSensorModel() if model is None else model
        cam = _compose(pose, mount)
        c, s = math.cos(cam[2]), math.sin(cam[2])
        status = np.asarray(scan.status_codes)
        px, py = np.asarray(scan.x), np.asarray(scan.y)
        nx, ny = np.asarray(scan.near_x), np.asarray(scan.near_y)
        rng = np.hypot(px, py)
        err = np.full(len(status), np.nan)
        bnd = status == 0
        if table is not None and bnd.any():
            err[bnd] = table.lookup_error(
                np.asarray(scan.columns, np.float64)[bnd], np.asarray(scan.rows)[bnd]
            )
        sigma = model.sigma_m(err, np.asarray(scan.footprints, np.float64), self.cell)
        # free space ends margin_sigmas before a boundary, never nearer than the near edge
        near_r = np.hypot(nx, ny)
        end_r = np.where(bnd, rng - model.margin_sigmas * sigma, rng)
        end_r = np.maximum(end_r, near_r)
        with np.errstate(invalid="ignore", divide="ignore"):
            scale = np.where(rng > 0, end_r / rng, 0.0)
        ex, ey = px * scale, py * scale
        seen = (status == ColumnStatus.BOUNDARY) | (status == ColumnStatus.NO_BOUNDARY)
        valid = seen & np.isfinite(ex + ey + nx + ny)

        def world(gx, gy):
            return cam[0] + c * gx - s * gy, cam[1] + s * gx + c * gy

        ncx, ncy = self.to_cells(*world(nx, ny))
        ecx, ecy = self.to_cells(*world(ex, ey))
        cam_c = self.to_cells(cam[0], cam[1])
        mask = self._fan(np.stack([ncx, ncy], 1), np.stack([ecx, ecy], 1), valid, cam_c)
        r_img = self._range_image(mask, cam_c)
        free_nats = model.fusion_weight * model.free_logit(r_img)
        hit = np.full(mask.shape, np.nan, np.float32)
        bcx, bcy = self.to_cells(*world(px, py))
        hit_nats = model.fusion_weight * model.hit_logit(rng)
        ok = bnd & np.isfinite(bcx + bcy)
        rad = np.maximum(np.nan_to_num(sigma) / self.cell, 0.5)
        gap = np.hypot(np.diff(px), np.diff(py))
        near = np.zeros(len(status), bool)
        near[:-1] = ok[:-1] & ok[1:] & (gap < 2.0 * (sigma[:-1] + sigma[1:]) + 2 * self.cell)
        _stamp_hits(hit, bcx, bcy, rad, hit_nats, ok, near)
        tc = (status == 2) & np.isfinite(nx + ny)
        if tc.any():
            tx, ty = self.to_cells(*world(nx[tc], ny[tc]))
            ok = (tx >= 0) & (tx < self.n) & (ty >= 0) & (ty < self.n)
            hit[ty[ok].astype(int), tx[ok].astype(int)] = (
                model.fusion_weight * model.too_close_logit
            )
        self._apply(mask, free_nats, hit)

    def mark_bump(self, pose, bearing_rad: float, distance_m: float) -> None:
        """A bumper contact: cells on an arc of +-0.6 rad around ``bearing_rad`` (robot frame)
        at ``distance_m`` from ``pose`` become obstacles in a separate bumper layer, which the
        camera cannot clear (it may not see what the bumper felt) and which forgets ten times
        slower than the evidence."""
        a = pose[2] + bearing_rad + np.linspace(-0.6, 0.6, 13)
        cx, cy = self.to_cells(pose[0] + distance_m * np.cos(a), pose[1] + distance_m * np.sin(a))
        ok = (cx >= 0) & (cx < self.n) & (cy >= 0) & (cy < self.n)
        self.bumps[cy[ok].astype(int), cx[ok].astype(int)] = 1.0

    def insert_laser(
        self,
        ranges: np.ndarray,
        angles: np.ndarray,
        pose,
        *,
        range_max_m: float,
        hit_nats: float = 2.2,
        miss_nats: float = -2.0,
    ) -> None:
        """An ideal 2-D laser scan (REP 117 ranges [m] at ``angles`` [rad, robot frame]) from
        ``pose``: free up to each return (or ``range_max_m``), occupied at the return.
        Evidence defaults: p = 0.9 / 0.12, an ideal sensor's strong constant evidence."""
        r = np.asarray(ranges, np.float64)
        a = np.asarray(angles, np.float64) + pose[2]
        end = np.where(np.isfinite(r), r, range_max_m)
        ex, ey = pose[0] + end * np.cos(a), pose[1] + end * np.sin(a)
        ecx, ecy = self.to_cells(ex, ey)
        pc = self.to_cells(pose[0], pose[1])
        near = np.tile(np.array(pc, np.float64), (len(r), 1))
        valid = np.isfinite(ecx + ecy)
        mask = self._fan(near, np.stack([ecx, ecy], 1), valid, pc)
        hit = np.full(mask.shape, np.nan, np.float32)
        h = np.isfinite(r)
        hx, hy = ecx[h].astype(int), ecy[h].astype(int)
        ok = (hx >= 0) & (hx < self.n) & (hy >= 0) & (hy < self.n)
        hit[hy[ok], hx[ok]] = hit_nats
        self._apply(mask, np.full(mask.shape, miss_nats, np.float32), hit)
