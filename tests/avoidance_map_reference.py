"""The avoidance map's insertions as first written with numpy and OpenCV (``cv2.fillPoly`` for
the floor quadrilaterals): the reference the Rust core (``floorscan_core::avoidance_map``) must
equal cell for cell (tests/drive/test_avoidance_map_native.py) and the baseline of
bench/drive_step.py. Shares only the map's geometry with the package."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np
from floorscan.drive.avoidance_map import AvoidanceMap, _compose
from floorscan.drive.sensor_model import VisualSensorModel
from floorscan.ranging.scan import ColumnStatus

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


class ReferenceAvoidanceMap(AvoidanceMap):
    """:class:`~floorscan.drive.AvoidanceMap` with the numpy/OpenCV insertions and decay."""

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
