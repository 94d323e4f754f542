"""Estimating the :class:`VisualSensorModel` from simulator truth, and checking that the
avoidance map's probabilities mean what they say (a reliability diagram).

:func:`fit_sensor_model` inserts each frame of a simulated run (true poses) into a fresh map
with unit evidence, and regresses the truth of the cells each frame marks: logit P(occupied)
against range, separately for cells seen free and cells marked as boundary (logistic
regression, Newton's method). :func:`fit_fusion_weight` then picks the evidence multiplier
whose fused map has the lowest log loss against the truth.
"""

from __future__ import annotations

import math
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..drive.avoidance_map import AvoidanceMap, AvoidanceMapOptions, _compose
from ..drive.sensor_model import VisualSensorModel
from ..options import defaults
from ..ranging.ranger import VisualRanger
from .scoring import sample_truth


def _logistic_fit(x: np.ndarray, y: np.ndarray, iters: int = 30) -> Tuple[float, float]:
    X = np.stack([np.ones_like(x), x], 1)
    w = np.zeros(2)
    for _ in range(iters):
        p = 1 / (1 + np.exp(-X @ w))
        g = X.T @ (y - p)
        H = (X * (p * (1 - p))[:, None]).T @ X + 1e-6 * np.eye(2)
        w = w + np.linalg.solve(H, g)
    return float(w[0]), float(w[1])


def _cells_truth(amap: AvoidanceMap, raster) -> np.ndarray:
    n = amap.n
    jj, ii = np.mgrid[0:n, 0:n]
    x = amap.origin_m[0] + (ii + 0.5) * amap.cell
    y = amap.origin_m[1] + (jj + 0.5) * amap.cell
    return sample_truth(
        raster.cells, raster.origin, raster.resolution_m, x.ravel(), y.ravel()
    ).reshape(n, n)


def _frame_samples(run, k, scan, table, raster, cell):
    """(range, truth) of the cells frame k marks free and of those it marks as hits."""
    unit = VisualSensorModel(
        free_a=-1.0, free_b=0.0, hit_a=1.0, hit_b=0.0, too_close_logit=0.0, fusion_weight=1.0
    )
    pose = tuple(run.poses[k])
    m = AvoidanceMap(
        AvoidanceMapOptions(
            cell_size_m=cell,
            clamp_nats=(-5, 5),
            probability_scale=1.0,
            probability_offset=0.0,
            probability_knots=None,
        ),
        center=pose[:2],
    )
    m.insert_visual(scan, pose, mount=run.camera.robot_from_camera, table=table, model=unit)
    truth = _cells_truth(m, raster)
    cam = _compose(pose, tuple(run.camera.robot_from_camera))
    n = m.n
    jj, ii = np.mgrid[0:n, 0:n]
    r = np.hypot(
        m.origin_m[0] + (ii + 0.5) * cell - cam[0], m.origin_m[1] + (jj + 0.5) * cell - cam[1]
    )
    known = truth >= 0
    free = (m.log_odds < -0.5) & known
    hit = (m.log_odds > 0.5) & known
    return (r[free], truth[free] == 100), (r[hit], truth[hit] == 100)


def fit_sensor_model(
    runs: Sequence,
    table,
    *,
    cell_size_m: Optional[float] = None,
    every: int = 3,
    base: Optional[VisualSensorModel] = None,
) -> Tuple[VisualSensorModel, Dict]:
    """Fits free_a/free_b and hit_a/hit_b on simulated runs (with truth) ranged with
    ``table``; returns the model and the sample counts."""
    base = VisualSensorModel() if base is None else base
    cell_size_m = _cell(cell_size_m)
    ranger = VisualRanger(table, columns=defaults("drive_run")["columns"])  # the drive's
    fr, fy, hr, hy = [], [], [], []
    for run in runs:
        raster = run.world.occupancy(resolution_m=cell_size_m)
        for k in range(0, len(run.timestamps), every):
            scan = ranger.scan(run.images[k], timestamp=float(run.timestamps[k]))
            (a, b), (c, d) = _frame_samples(run, k, scan, table, raster, cell_size_m)
            fr.append(a), fy.append(b), hr.append(c), hy.append(d)
    fr, fy = np.concatenate(fr), np.concatenate(fy).astype(float)
    hr, hy = np.concatenate(hr), np.concatenate(hy).astype(float)
    free_a, free_b = _logistic_fit(fr, fy)
    hit_a, hit_b = _logistic_fit(hr, hy)
    model = base.with_(free_a=free_a, free_b=free_b, hit_a=hit_a, hit_b=hit_b)
    return model, {
        "free_cells": int(fr.size),
        "free_occupied_share": float(fy.mean()),
        "hit_cells": int(hr.size),
        "hit_occupied_share": float(hy.mean()),
    }


def fused_map(
    run, table, model, *, cell_size_m=None, frames=None, map_options=None
) -> AvoidanceMap:
    """The avoidance map (no forgetting) after ``frames`` of ``run`` with true poses."""
    ranger = VisualRanger(table, columns=defaults("drive_run")["columns"])  # the drive's

    base = map_options or AvoidanceMapOptions(
        probability_scale=1.0, probability_offset=0.0, probability_knots=None
    )
    opts = base.replace(cell_size_m=_cell(cell_size_m), size_m=40.0, half_life_s=None)
    m = AvoidanceMap(opts, center=tuple(run.poses[0])[:2])
    for k in range(len(run.timestamps)) if frames is None else frames:
        pose = tuple(run.poses[k])
        m.recenter(*pose[:2])
        scan = ranger.scan(run.images[k], timestamp=float(run.timestamps[k]))
        m.insert_visual(scan, pose, mount=run.camera.robot_from_camera, table=table, model=model)
    return m


def reliability(amap: AvoidanceMap, raster) -> List[Dict]:
    """Per decile of predicted occupancy probability over the cells the map has evidence
    on (|log odds| > 0.05) and the truth knows: mean prediction, observed frequency of
    occupied, cell count, and the observed frequency's 95 % Wilson interval
    (``observed_low``, ``observed_high``). Pool several maps with :func:`reliability_cells`
    and :func:`reliability_of`."""
    return reliability_of(*reliability_cells(amap, raster))


def reliability_cells(amap: AvoidanceMap, raster) -> Tuple[np.ndarray, np.ndarray]:
    """The predicted occupancy probabilities of the cells the map has evidence on
    (|log odds| > 0.05) and the truth knows, and whether each is occupied in truth."""
    truth = _cells_truth(amap, raster)
    p = amap.probabilities()
    sel = (np.abs(amap.log_odds) > 0.05) & (truth >= 0)
    return p[sel], truth[sel] == 100


def wilson_interval(successes: int, n: int, z: float = 1.96) -> Tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % at z = 1.96)."""
    if n <= 0:
        return 0.0, 1.0
    f = successes / n
    d = 1 + z * z / n
    centre = (f + z * z / (2 * n)) / d
    half = z * math.sqrt(f * (1 - f) / n + z * z / (4 * n * n)) / d
    return max(0.0, centre - half), min(1.0, centre + half)


def reliability_of(p: np.ndarray, occupied: np.ndarray) -> List[Dict]:
    """The reliability diagram (see :func:`reliability`) of predictions ``p`` against the
    truth ``occupied`` (bool), one row per non-empty decile."""
    p, occupied = np.asarray(p, np.float64), np.asarray(occupied, bool)
    out = []
    for d in range(10):
        lo, hi = d / 10, (d + 1) / 10
        s = (p >= lo) & ((p < hi) if d < 9 else (p <= hi))
        if s.any():
            n, k = int(s.sum()), int(occupied[s].sum())
            low, high = wilson_interval(k, n)
            out.append(
                {
                    "decile": f"{lo:.1f}-{hi:.1f}",
                    "predicted": float(p[s].mean()),
                    "observed": k / n,
                    "cells": n,
                    "observed_low": low,
                    "observed_high": high,
                }
            )
    return out


def log_loss(amap: AvoidanceMap, raster) -> float:
    truth = _cells_truth(amap, raster)
    p = np.clip(amap.probabilities(), 1e-6, 1 - 1e-6)
    sel = (np.abs(amap.log_odds) > 0.05) & (truth >= 0)
    y = truth[sel] == 100
    return float(-np.mean(np.where(y, np.log(p[sel]), np.log(1 - p[sel]))))


def fit_probability_calibration(runs, table, model, *, cell_size_m=None):
    """Platt scaling: (scale, offset) with P(occupied) = logistic(scale * L + offset) over
    the fused maps' cells with evidence, against the truth."""
    x, y = _cells_with_evidence(runs, table, model, cell_size_m)
    b, a = _logistic_fit(x, y)
    return a, b


def _cell(cell_size_m: Optional[float]) -> float:
    """The cell size given, or the avoidance map's default."""
    return AvoidanceMapOptions().cell_size_m if cell_size_m is None else float(cell_size_m)


def _cells_with_evidence(runs, table, model, cell_size_m):
    cell_size_m = _cell(cell_size_m)
    xs, ys = [], []
    for run in runs:
        raster = run.world.occupancy(resolution_m=cell_size_m)
        m = fused_map(run, table, model, cell_size_m=cell_size_m)
        truth = _cells_truth(m, raster)
        sel = (np.abs(m.log_odds) > 0.05) & (truth >= 0)
        xs.append(m.log_odds[sel].astype(np.float64))
        ys.append((truth[sel] == 100).astype(np.float64))
    return np.concatenate(xs), np.concatenate(ys)


def isotonic(x: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Pool-adjacent-violators: the non-decreasing fit of ``y`` (ordered by ``x``, weights
    ``w``) with the least weighted squared error."""
    order = np.argsort(x, kind="stable")
    vals, wts, sizes = [], [], []
    for v, wt in zip(y[order].tolist(), w[order].tolist()):
        vals.append(v)
        wts.append(wt)
        sizes.append(1)
        while len(vals) > 1 and vals[-2] > vals[-1]:
            wsum = wts[-2] + wts[-1]
            v2 = (vals[-2] * wts[-2] + vals[-1] * wts[-1]) / wsum
            n2 = sizes[-2] + sizes[-1]
            del vals[-1], wts[-1], sizes[-1]
            vals[-1], wts[-1], sizes[-1] = v2, wsum, n2
    fit = np.repeat(vals, sizes)
    out = np.empty_like(fit)
    out[order] = fit
    return out


def fit_probability_knots(runs, table, model, *, bins: int = 24, cell_size_m=None):
    """Isotonic calibration of the fused maps' log odds against the truth: the cells with
    evidence are grouped into ``bins`` quantile bins of log odds, the bins' occupied
    frequencies made non-decreasing (pool-adjacent-violators, weighted by cell count); the
    knots are (mean log odds, calibrated frequency) per bin, for
    ``AvoidanceMapOptions.probability_knots``."""
    x, y = _cells_with_evidence(runs, table, model, cell_size_m)
    edges = np.unique(np.quantile(x, np.linspace(0, 1, bins + 1)))
    idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    n = np.bincount(idx, minlength=len(edges) - 1).astype(np.float64)
    keep = n > 0
    mx = np.bincount(idx, weights=x, minlength=len(n))[keep] / n[keep]
    my = np.bincount(idx, weights=y, minlength=len(n))[keep] / n[keep]
    fy = isotonic(mx, my, n[keep])
    mx, fy = np.unique(mx), fy[np.unique(mx, return_index=True)[1]]
    return tuple((round(float(a), 4), round(float(b), 4)) for a, b in zip(mx, fy))


def fit_fusion_weight(
    runs, table, model, *, weights=(0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.85, 1.0), cell_size_m=None
):
    """The fusion weight with the lowest log loss of the fused maps."""
    cell_size_m = _cell(cell_size_m)
    best = None
    for w in weights:
        m2 = model.with_(fusion_weight=w)
        loss = 0.0
        for run in runs:
            raster = run.world.occupancy(resolution_m=cell_size_m)
            loss += log_loss(fused_map(run, table, m2, cell_size_m=cell_size_m), raster)
        if best is None or loss < best[1]:
            best = (w, loss)
    return model.with_(fusion_weight=best[0]), best[1]
