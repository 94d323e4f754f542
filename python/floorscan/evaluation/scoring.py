"""Scoring against ground truth: boundary points against the true obstacle base, maps against
the true occupancy. Used by ``floorscan demo`` and ``floorscan eval``; works with any source of
truth in the documented forms (per-column truth arrays, a map_server map or raster)."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from ..ranging.scan import STATUS_NAMES, ColumnStatus, Scan

BOUNDARY, NO_BOUNDARY, TOO_CLOSE, INVALID = (
    ColumnStatus.BOUNDARY,
    ColumnStatus.NO_BOUNDARY,
    ColumnStatus.TOO_CLOSE,
    ColumnStatus.INVALID,
)
RANGE_BANDS_M = ((0.0, 1.0), (1.0, 2.0), (2.0, 3.0), (3.0, float("inf")))


@dataclass
class ColumnScores:
    """Per sampled column of one frame: whether it is wrong, and the point error [m] where both
    the scan and the truth have a boundary (NaN elsewhere)."""

    wrong: np.ndarray
    error_m: np.ndarray
    true_range_m: np.ndarray
    scan_status: np.ndarray
    true_status: np.ndarray


def score_columns(
    scan: Scan, true_status: np.ndarray, true_points: np.ndarray, *, tolerance_m: float = 0.10
) -> ColumnScores:
    """Scores one scan against per-image-column truth: ``true_status`` (W,) status codes and
    ``true_points`` (W, 2) true boundary points in the camera ground frame [m].

    A column is wrong when its status differs from the truth, or when both say boundary and the
    points are more than ``tolerance_m`` apart. Not wrong: ``invalid`` where the truth has no
    boundary (the camera was not calibrated there), and ``no_boundary`` where the true boundary
    lies beyond the farthest point the column scanned (its range limit)."""
    cols = scan.columns.astype(np.intp)
    ts = np.asarray(true_status)[cols].astype(np.int64)
    tp = np.asarray(true_points, dtype=np.float64)[cols]
    ss = scan.status_codes.astype(np.int64)
    both = (ss == BOUNDARY) & (ts == BOUNDARY)
    err = np.full(len(cols), np.nan)
    err[both] = np.hypot(scan.x[both] - tp[both, 0], scan.y[both] - tp[both, 1])
    status_wrong = (ss != ts) & ~((ss == INVALID) & (ts != BOUNDARY))
    # "Free as far as the camera sees": a true boundary beyond the farthest point the column
    # scanned (its range limit) is not a miss.
    scanned_m = np.hypot(scan.x, scan.y)
    beyond = (
        (ss == NO_BOUNDARY)
        & (ts == BOUNDARY)
        & (np.hypot(tp[:, 0], tp[:, 1]) > scanned_m - tolerance_m)
    )
    status_wrong &= ~beyond
    wrong = status_wrong | (both & (err > tolerance_m))
    true_range = np.hypot(tp[:, 0], tp[:, 1])
    return ColumnScores(wrong, err, true_range, ss, ts)


@dataclass
class BoundarySummary:
    columns: int
    error_rate: float
    """Share of sampled columns that are wrong (status or > tolerance)."""
    boundary_points: int
    far_point_share: float
    """Share of reported boundary points more than the tolerance from the true obstacle base
    (or where the truth has no boundary)."""
    median_error_cm: float
    p90_error_cm: float
    by_range: Dict[str, Dict[str, float]]

    def as_dict(self) -> Dict[str, object]:
        return asdict(self)


def summarise_columns(
    scores: Sequence[ColumnScores], *, tolerance_m: float = 0.10
) -> BoundarySummary:
    wrong = np.concatenate([s.wrong for s in scores]) if scores else np.zeros(0, bool)
    err = np.concatenate([s.error_m for s in scores]) if scores else np.zeros(0)
    rng = np.concatenate([s.true_range_m for s in scores]) if scores else np.zeros(0)
    ss = np.concatenate([s.scan_status for s in scores]) if scores else np.zeros(0, np.int64)
    ts = np.concatenate([s.true_status for s in scores]) if scores else np.zeros(0, np.int64)
    reported = ss == BOUNDARY
    far = reported & ((ts != BOUNDARY) | (np.nan_to_num(err, nan=np.inf) > tolerance_m))
    finite = err[np.isfinite(err)]
    by_range = {}
    for lo, hi in RANGE_BANDS_M:
        m = np.isfinite(err) & (rng >= lo) & (rng < hi)
        key = f"{lo:g}-{hi:g} m" if np.isfinite(hi) else f"{lo:g}+ m"
        by_range[key] = {
            "points": int(m.sum()),
            "median_cm": float(np.median(err[m]) * 100) if m.any() else float("nan"),
            "p90_cm": float(np.percentile(err[m], 90) * 100) if m.any() else float("nan"),
        }
    return BoundarySummary(
        columns=int(wrong.size),
        error_rate=float(wrong.mean()) if wrong.size else float("nan"),
        boundary_points=int(reported.sum()),
        far_point_share=float(far.sum() / max(reported.sum(), 1)),
        median_error_cm=float(np.median(finite) * 100) if finite.size else float("nan"),
        p90_error_cm=float(np.percentile(finite, 90) * 100) if finite.size else float("nan"),
        by_range=by_range,
    )


@dataclass
class MapScores:
    known_cells: int
    agreement: float
    """Share of the cells both the map and the truth know on which they agree (occupied or not)."""
    occupied_precision: float
    occupied_recall: float

    def as_dict(self) -> Dict[str, object]:
        return asdict(self)


def sample_truth(
    truth_cells: np.ndarray,
    truth_origin: Tuple[float, float],
    truth_resolution_m: float,
    x: np.ndarray,
    y: np.ndarray,
) -> np.ndarray:
    """Truth values (100 occupied, 0 free, -1 unknown; nav_msgs convention, row 0 = lowest y)
    at world points; -1 outside the raster."""
    i = np.floor((x - truth_origin[0]) / truth_resolution_m).astype(np.int64)
    j = np.floor((y - truth_origin[1]) / truth_resolution_m).astype(np.int64)
    h, w = truth_cells.shape
    inside = (i >= 0) & (i < w) & (j >= 0) & (j < h)
    out = np.full(x.shape, -1, dtype=np.int16)
    out[inside] = truth_cells[j[inside], i[inside]]
    return out


def score_map(
    classes: np.ndarray,
    origin_m: Tuple[float, float],
    cell_size_m: float,
    truth_cells: np.ndarray,
    truth_origin: Tuple[float, float],
    truth_resolution_m: float,
    *,
    mask: Optional[np.ndarray] = None,
) -> MapScores:
    """Scores a map's classes (H, W; 0 free, 1 unknown, 2 occupied; row 0 = lowest y; origin
    = lower-left corner [m]) against a true raster sampled at the map's cell centres."""
    h, w = classes.shape
    ys, xs = np.mgrid[0:h, 0:w]
    cx = origin_m[0] + (xs + 0.5) * cell_size_m
    cy = origin_m[1] + (ys + 0.5) * cell_size_m
    truth = sample_truth(truth_cells, truth_origin, truth_resolution_m, cx, cy)
    known = (classes != 1) & (truth >= 0)
    if mask is not None:
        known &= mask
    pred_occ = classes == 2
    true_occ = truth == 100
    agree = pred_occ == true_occ
    tp = int((pred_occ & true_occ & known).sum())
    return MapScores(
        known_cells=int(known.sum()),
        agreement=float(agree[known].mean()) if known.any() else float("nan"),
        occupied_precision=tp / max(int((pred_occ & known).sum()), 1),
        occupied_recall=tp / max(int((true_occ & known).sum()), 1),
    )


def status_name(code: int) -> str:
    return STATUS_NAMES[int(code)]
