"""The avoidance map as first written with numpy and OpenCV (``cv2.fillPoly`` for
the floor quadrilaterals): the reference the Rust core (``floorscan_core::avoidance_map``) must
equal cell for cell (tests/drive/test_avoidance_map_native.py)."""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np
from floorscan.drive.avoidance_map import AvoidanceMapOptions, _compose
from floorscan.drive.sensor_model import VisualSensorModel
from floorscan.mapping.grid_views import GridExtent
from floorscan.ranging.scan import ColumnStatus

_NO_EVIDENCE = 0.05
_LAYERS = (
    "log_odds",
    "bumps",
    "confirmed",
    "plan_log_odds",
    "plan_confirmed",
    "plan_near_hits",
)


def _logit(p: float) -> float:
    return math.log(p / (1.0 - p))


_SHIFT = 4  # sub-cell precision of rasterised polygons: 1 / 16 cell


def stamp_hits(
    hit, cx, cy, rad, values, ok, near, confirms=None, far=None, unheld=None, held=None
) -> None:
    """Draws into ``hit`` (n, n) the discs of radius ``rad`` [cells] around the boundary
    points (cx, cy) [fractional cells: cell k spans [k, k + 1)] where ``ok``, each with its
    ``values`` entry (the cells whose centre lies within the radius), and the segments from
    point k to k + 1 where ``near[k]`` with the smaller of the two values (the cells the
    segment passes through, sampled every half cell); into ``confirms`` (n, n) bool, where
    given, each point's ``far`` flag on its disc and both points' on their segment; into
    ``unheld`` (n, n) bool, where given, each point's ``held`` flag on its disc and either
    point's on their segment."""
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
        if confirms is not None:
            flags = np.broadcast_to(far[idx][:, None], pi.shape)
            confirms[pj[inside].astype(np.int64), pi[inside].astype(np.int64)] = flags[inside]
        if unheld is not None:
            flags = np.broadcast_to(held[idx][:, None], pi.shape)
            unheld[pj[inside].astype(np.int64), pi[inside].astype(np.int64)] = flags[inside]
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
        if confirms is not None:
            both = np.broadcast_to((far[seg] & far[seg + 1])[:, None], pi.shape)
            confirms[pj[inside].astype(np.int64), pi[inside].astype(np.int64)] = both[inside]
        if unheld is not None:
            either = np.broadcast_to((held[seg] | held[seg + 1])[:, None], pi.shape)
            unheld[pj[inside].astype(np.int64), pi[inside].astype(np.int64)] = either[inside]


class ReferenceAvoidanceMap:
    """:class:`~floorscan.drive.AvoidanceMap` as first written: numpy layers, the numpy/OpenCV
    insertions, scrolling and views."""

    def __init__(self, options: Optional[AvoidanceMapOptions] = None, *, center=(0, 0)):
        options = AvoidanceMapOptions() if options is None else options
        self.options = options
        self.cell = options.cell_size_m
        self.n = int(round(options.size_m / self.cell))
        self.log_odds = np.zeros((self.n, self.n), np.float32)
        self.bumps = np.zeros((self.n, self.n), np.float32)
        # 1 where a hit from VisualSensorModel.confirm_range_m or farther confirmed the cell
        self.confirmed = np.zeros((self.n, self.n), np.uint8)
        # the planner's layers: the same evidence, but a confirmed obstacle that the floor
        # seen beyond it contradicts clears by VisualSensorModel.confirmed_clearing of it a
        # frame (log_odds clear in full, so probabilities() keeps its calibration)
        self.plan_log_odds = np.zeros((self.n, self.n), np.float32)
        self.plan_confirmed = np.zeros((self.n, self.n), np.uint8)
        # 1 where the last visual insertion hit from nearer than
        # VisualSensorModel.persist_range_m: such a hit enters the planner's layers when the
        # next one hits there again (or the planner has evidence the place is occupied)
        self.plan_near_hits = np.zeros((self.n, self.n), np.uint8)
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
        for name in _LAYERS:
            layer = getattr(self, name)
            out = np.zeros_like(layer)
            if abs(dx) < n and abs(dy) < n:
                src = layer[max(dy, 0) : n + min(dy, 0), max(dx, 0) : n + min(dx, 0)]
                out[max(-dy, 0) : n + min(-dy, 0), max(-dx, 0) : n + min(-dx, 0)] = src
            setattr(self, name, out)
        self.x_cell, self.y_cell = cx, cy

    def to_cells(self, x, y):
        """World (odometry frame) points [m] to fractional cell coordinates (col, row)."""
        return (np.asarray(x) / self.cell - self.x_cell, np.asarray(y) / self.cell - self.y_cell)

    # --- views ----------------------------------------------------------------------------
    def probabilities(self) -> np.ndarray:
        """Calibrated occupancy probabilities (``probability_knots``, or the Platt curve of
        ``probability_scale`` / ``probability_offset``); cells without evidence read 0.5."""
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
        evidence of the planner's layer against logit(free_threshold) /
        logit(occupied_threshold) (the calibrated probabilities of :meth:`probabilities` say
        how often such a decision is right; a single calibrated reading never reaches 0.65,
        and the map must still show it)."""
        c = np.ones(self.plan_log_odds.shape, np.uint8)
        c[self.known() & (self.plan_log_odds < self._plan_free)] = 0
        c[self.occupied()] = 2
        return c

    def known(self) -> np.ndarray:
        """Cells the planner has evidence for (either way)."""
        return np.abs(self.plan_log_odds) >= _NO_EVIDENCE

    def occupied(self) -> np.ndarray:
        """The planner's obstacles: raw evidence of the planner's layer above
        logit(occupied_threshold), before the output calibration (one confident reading
        suffices: for avoidance a missed obstacle costs more than a detour), or the bumper's
        marks."""
        return (self.plan_log_odds > self._plan_occ) | (self.bumps > 0.5)

    def mark_bump(self, pose, bearing_rad: float, distance_m: float) -> None:
        """A bumper contact: the cells on a straight face ``2 bump_face_half_length_m`` long,
        square to ``bearing_rad`` (robot frame) at ``distance_m`` from ``pose``, become
        obstacles in a separate bumper layer, which the camera cannot clear (it may not see
        what the bumper felt) and which forgets with ``bump_half_life_s``. A face, not the
        touched point: what a bumper meets is most often a flat side (a box, a desk, a wall)
        wider than the segment that felt it, and the robot should not bump along it point by
        point."""
        half_length_m = self.options.bump_face_half_length_m
        a = pose[2] + bearing_rad
        t = np.linspace(-half_length_m, half_length_m, int(4 * half_length_m / self.cell) + 2)
        px = pose[0] + distance_m * math.cos(a) - t * math.sin(a)
        py = pose[1] + distance_m * math.sin(a) + t * math.cos(a)
        cx, cy = self.to_cells(px, py)
        ok = (cx >= 0) & (cx < self.n) & (cy >= 0) & (cy < self.n)
        self.bumps[cy[ok].astype(int), cx[ok].astype(int)] = 1.0

    def decay(self, dt_s: float) -> None:
        hl, bump_hl = self.options.half_life_s, self.options.bump_half_life_s
        if hl is not None and dt_s > 0:
            self.log_odds *= np.float32(0.5 ** (dt_s / hl))
            self.plan_log_odds *= np.float32(0.5 ** (dt_s / hl))
        if bump_hl is not None and dt_s > 0:
            self.bumps *= np.float32(0.5 ** (dt_s / bump_hl))

    def _apply(
        self,
        free_mask,
        free_nats,
        hit_nats,
        weak=1.0,
        confirmed=0.0,
        confirms=None,
        confirmed_share=1.0,
        unheld=None,
    ) -> None:
        """The map's own layers (confirmed obstacles clear in full), then the planner's (by
        ``confirmed_share``; none from a hit that is ``unheld``)."""
        for L, C, share, skip in (
            (self.log_odds, self.confirmed, 1.0, None),
            (self.plan_log_odds, self.plan_confirmed, confirmed_share, unheld),
        ):
            self._apply_layer(
                L, C, free_mask, free_nats, hit_nats, weak, confirmed, confirms, share, skip
            )

    def _apply_layer(
        self,
        L,
        C,
        free_mask,
        free_nats,
        hit_nats,
        weak,
        confirmed,
        confirms,
        confirmed_share,
        skip=None,
    ) -> None:
        if skip is not None and skip.any():
            # a held-back hit leaves its cell's log odds as they were and confirms nothing
            L0 = L.copy()
            self._apply_layer(
                L, C, free_mask, free_nats, hit_nats, weak, confirmed, confirms & ~skip,
                confirmed_share,
            )  # fmt: skip
            L[skip] = L0[skip]
            return
        lo, hi = self.options.clamp_nats
        sel = (free_mask > 0) & ~np.isfinite(hit_nats) if hit_nats is not None else free_mask > 0
        # inside only quadrilaterals beside a no-boundary column (2), a cell believed occupied
        # (log odds above `confirmed`, confirmed by a hit from confirm_range_m or farther)
        # takes `weak` times its free evidence; inside a fully clearing one (1) such a cell
        # takes `confirmed_share` times it (visual scans only)
        believed = L > np.float32(confirmed)
        full_share = np.float32(1.0)
        if confirms is not None:
            C[L <= 0] = 0
            believed &= C != 0
            C[np.isfinite(hit_nats) & confirms] = 1
            full_share = np.float32(confirmed_share)
        scale = np.where((free_mask == 2) & believed, np.float32(weak), np.float32(1.0))
        scale = np.where((free_mask == 1) & believed, full_share, scale)
        L[sel] += (scale * free_nats)[sel]
        if hit_nats is not None:
            h = np.isfinite(hit_nats)
            L[h] += hit_nats[h]
        np.clip(L, lo, hi, out=L)

    def _fan(self, near_c, end_c, valid, cam_c, weak=None) -> np.ndarray:
        """The quadrilaterals' mask: 1, or 2 inside only those where ``weak`` (per pair)."""
        mask = np.zeros(self.log_odds.shape, np.uint8)
        pair = valid[:-1] & valid[1:]
        if weak is None:
            self._fill(mask, near_c, end_c, np.nonzero(pair)[0], cam_c, 1)
        else:
            self._fill(mask, near_c, end_c, np.nonzero(pair & weak)[0], cam_c, 2)
            self._fill(mask, near_c, end_c, np.nonzero(pair & ~weak)[0], cam_c, 1)
        return mask

    def _fill(self, mask, near_c, end_c, k, cam_c, value) -> None:
        import cv2

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
            cv2.fillPoly(mask, list(pts), value, lineType=cv2.LINE_8, shift=_SHIFT)

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
        weak = None
        if model.no_boundary_clearing < 1.0:
            nob = status == ColumnStatus.NO_BOUNDARY
            weak = nob[:-1] | nob[1:]
        mask = self._fan(np.stack([ncx, ncy], 1), np.stack([ecx, ecy], 1), valid, cam_c, weak=weak)
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
        confirms = np.zeros(mask.shape, bool)
        with np.errstate(invalid="ignore"):
            far = rng >= model.confirm_range_m
        held = self._held_back(status, ok, (px, py), (nx, ny), world, model)
        unheld = np.zeros(mask.shape, bool)
        stamp_hits(hit, bcx, bcy, rad, hit_nats, ok, near, confirms, far, unheld, held)
        tc = (status == 2) & np.isfinite(nx + ny)
        if tc.any():
            tx, ty = self.to_cells(*world(nx[tc], ny[tc]))
            ok = (tx >= 0) & (tx < self.n) & (ty >= 0) & (ty < self.n)
            hit[ty[ok].astype(int), tx[ok].astype(int)] = (
                model.fusion_weight * model.too_close_logit
            )
            confirms[ty[ok].astype(int), tx[ok].astype(int)] = (
                np.hypot(nx[tc], ny[tc])[ok] >= model.confirm_range_m
            )
            unheld[ty[ok].astype(int), tx[ok].astype(int)] = held[tc][ok]
        self._apply(
            mask,
            free_nats,
            hit,
            weak=model.no_boundary_clearing,
            confirmed=model.confirmed_nats,
            confirms=confirms,
            confirmed_share=model.confirmed_clearing,
            unheld=unheld & np.isfinite(hit),
        )

    def _held_back(self, status, ok, point, near_edge, world, model) -> np.ndarray:
        """Per reading: whether its hit (boundary point or ``too_close`` near edge) is nearer
        than ``persist_range_m`` and neither the last insertion hit its cell or a neighbour
        from that near nor the planner believes one of them occupied; rewrites
        ``plan_near_hits`` with this insertion's near hits."""
        gx = np.where(status == 0, np.where(ok, point[0], np.nan), np.nan)
        gy = np.where(status == 0, np.where(ok, point[1], np.nan), np.nan)
        gx = np.where(status == 2, near_edge[0], gx)
        gy = np.where(status == 2, near_edge[1], gy)
        with np.errstate(invalid="ignore"):
            near = np.hypot(gx, gy) < model.persist_range_m
            cx, cy = self.to_cells(*world(gx, gy))
            inside = (cx >= 0) & (cx < self.n) & (cy >= 0) & (cy < self.n)
        i = np.where(inside, cx, 0).astype(np.int64)
        j = np.where(inside, cy, 0).astype(np.int64)
        before = np.pad((self.plan_near_hits != 0) | (self.plan_log_odds > 0), 1)
        seen = np.zeros(len(status), bool)
        for dj in range(3):
            for di in range(3):
                seen |= before[j + dj, i + di]
        held = near & ~(inside & seen)
        self.plan_near_hits[:] = 0
        self.plan_near_hits[j[near & inside], i[near & inside]] = 1
        return held

    def insert_laser(
        self, ranges, angles, pose, *, range_max_m, hit_nats=2.2, miss_nats=-2.0
    ) -> None:
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
