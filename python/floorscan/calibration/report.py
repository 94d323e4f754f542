"""What a calibration measured: the points found, how well the table reproduces each of them,
how well it predicts each when fitted without it, the model chosen, the ground it covers and the
predicted error by range ring."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from .._atomic import PathLike, write_atomic
from .camera_model import CameraModel
from .pattern import Pattern
from .region import FieldOfView

RING_STEP_M = 0.5
"""Width of the report's range rings [m]."""


@dataclass(frozen=True)
class RangeRing:
    """Predicted error of the table's nodes between ``near_m`` and ``far_m`` [m] of range:
    ``median_cm``, ``p90_cm`` and ``max_cm`` over the nodes where the model sees floor,
    ``trusted_share`` the share of those the table keeps (NaN figures where none)."""

    near_m: float
    far_m: float
    nodes: int
    median_cm: float
    p90_cm: float
    max_cm: float
    trusted_share: float

    def to_dict(self) -> Dict[str, Any]:
        return {k: _json_number(v) if isinstance(v, float) else v for k, v in self.__dict__.items()}


def range_rings(
    range_m: np.ndarray, error_m: np.ndarray, valid: np.ndarray, kept: np.ndarray, max_m: float
) -> List[RangeRing]:
    """Rings of ``RING_STEP_M`` out to ``max_m`` [m] over node arrays."""
    out = []
    edges = np.arange(0.0, max_m + 1e-9, RING_STEP_M)
    if edges[-1] < max_m:
        edges = np.append(edges, max_m)
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = valid & (range_m >= lo) & (range_m < hi)
        e = error_m[m]
        e = e[np.isfinite(e)]
        n = int(m.sum())
        out.append(
            RangeRing(
                float(lo),
                float(hi),
                n,
                float(100 * np.median(e)) if e.size else float("nan"),
                float(100 * np.quantile(e, 0.9)) if e.size else float("nan"),
                float(100 * e.max()) if e.size else float("nan"),
                float(np.sum(kept & m) / n) if n else float("nan"),
            )
        )
    return out


def _rms(a: np.ndarray) -> float:
    """RMS of the finite values (points the table covers)."""
    a = np.asarray(a, float)
    a = a[np.isfinite(a)]
    return float(np.sqrt(np.mean(a * a))) if a.size else float("nan")


def _max(a: np.ndarray) -> float:
    a = np.asarray(a, float)
    a = a[np.isfinite(a)]
    return float(np.max(a)) if a.size else float("nan")


def _json_number(x: float, digits: int = 6):
    """A float for JSON: rounded, None for NaN and infinities."""
    return None if not np.isfinite(x) else round(float(x), digits)


@dataclass
class CalibrationReport:
    """The outcome of :func:`floorscan.calibrate`.

    Per pattern point (M found, in pattern order: rows away from the camera, left to right):

    - ``image_points``: (M, 2) [px] where it was found (u, v).
    - ``ground_points``: (M, 2) [m] where the pattern says it is (camera ground frame).
    - ``indices``: (M, 2) its pattern coordinates (i across, j away).
    - ``residual_m``: (M,) [m] distance between the table's ground point at ``image_points``
      (model plus bilinear interpolation) and ``ground_points``; NaN where the table has none.
    - ``loo_m``: (M,) [m] leave-one-out error: the table's error at the point when fitted
      without it (the model refitted without it, plus the table's interpolation error there).
    - ``used``: (M,) bool, False for points left out of the fit as outliers (a misplaced
      detection); the summary figures cover the used points.

    And: ``points_expected`` (the patterns' count), ``method`` (the detector), ``model`` (the
    fitted :class:`CameraModel`: lens and pose), ``model_name`` (its lens family, e.g.
    ``kb1``), ``candidates`` (each family tried and its held-out error [px], block
    cross-validation), ``plausible`` (the families whose disagreement counts into the error
    bars), ``error_inflation`` (the bars' calibration factor), ``noise_px`` (estimated corner
    noise), ``rings`` (:class:`RangeRing`: predicted error by range), ``field_of_view``
    (:class:`FieldOfView`), ``image_size`` (W, H), ``spacing_px``, ``coverage``,
    ``max_error_fraction``, ``max_range_m``, ``intrinsics_given``, ``views`` (images),
    ``margin_m``, ``near_field``, ``pattern`` (of the first image), ``loo_kind`` (``refit``
    or ``residual``), ``timings_s`` (seconds per stage: detect, fit, table, leave_one_out,
    report), ``notes`` (points left out, and why).
    """

    pattern: Pattern
    method: str
    image_size: Tuple[int, int]
    points_expected: int
    image_points: np.ndarray
    ground_points: np.ndarray
    indices: np.ndarray
    residual_m: np.ndarray
    loo_m: np.ndarray
    used: np.ndarray
    model: CameraModel
    model_name: str
    candidates: List[Tuple[str, float]]
    field_of_view: FieldOfView
    spacing_px: int
    margin_m: float
    plausible: List[str] = field(default_factory=list)
    error_inflation: float = 1.0
    noise_px: float = float("nan")
    coverage: str = "trusted"
    max_error_fraction: float = 0.03
    max_range_m: float = 3.0
    rings: List[RangeRing] = field(default_factory=list)
    intrinsics_given: bool = False
    views: int = 1
    near_field: bool = True
    loo_kind: str = "refit"
    timings_s: Dict[str, float] = field(default_factory=dict)
    notes: List[str] = field(default_factory=list)

    # --- figures ------------------------------------------------------------------------
    @property
    def points_found(self) -> int:
        return len(self.image_points)

    @property
    def extrapolate(self) -> bool:
        """True when the table keeps every node the model sees floor at (``coverage="all"``)."""
        return self.coverage == "all"

    def ring(self, range_m: float) -> Optional[RangeRing]:
        """The range ring holding ``range_m`` [m]."""
        return next((r for r in self.rings if r.near_m <= range_m < r.far_m), None)

    @property
    def points_used(self) -> int:
        return int(np.sum(self.used))

    @property
    def residual_rms_cm(self) -> float:
        return 100 * _rms(self.residual_m[self.used])

    @property
    def residual_max_cm(self) -> float:
        return 100 * _max(self.residual_m[self.used])

    @property
    def loo_rms_cm(self) -> float:
        return 100 * _rms(self.loo_m[self.used])

    @property
    def loo_max_cm(self) -> float:
        return 100 * _max(self.loo_m[self.used])

    def summary(self) -> str:
        """One line: points, residual and leave-one-out errors, ground range, model."""
        near, far = self.field_of_view.range_m
        return (
            f"{self.points_found}/{self.points_expected} points ({self.method})"
            + (
                f", {self.points_found - self.points_used} left out as outliers"
                if self.points_used < self.points_found
                else ""
            )
            + "; "
            f"residual RMS {self.residual_rms_cm:.2f} cm, max {self.residual_max_cm:.2f} cm; "
            f"leave-one-out RMS {self.loo_rms_cm:.2f} cm, max {self.loo_max_cm:.2f} cm; "
            f"ground {near:.2f}..{far:.2f} m ({self.coverage}); model {self.model_name}"
            + (" (intrinsics given)" if self.intrinsics_given else "")
            + (f"; predicted error {self._ring_summary()}" if self.rings else "")
        )

    def _ring_summary(self) -> str:
        parts = []
        for r in self.rings:
            if r.far_m in (1.0, 2.0, 3.0) or r is self.rings[-1]:
                inner = [q for q in self.rings if r.far_m - 1.0 <= q.near_m < r.far_m]
                kept = sum(q.trusted_share * q.nodes for q in inner if q.nodes)
                nodes = sum(q.nodes for q in inner)
                p90 = max((q.p90_cm for q in inner if q.nodes), default=float("nan"))
                if nodes:
                    parts.append(
                        f"{inner[0].near_m:.0f}-{r.far_m:.0f} m p90 {p90:.1f} cm "
                        f"({100 * kept / nodes:.0f} % kept)"
                    )
        return ", ".join(parts)

    # --- files --------------------------------------------------------------------------
    def metadata(self) -> Dict[str, Any]:
        """The summary kept in the table's metadata (``table.metadata["calibration"]``)."""
        return {
            "summary": self.summary(),
            "pattern": self.pattern.to_dict(),
            "method": self.method,
            "points_found": self.points_found,
            "points_expected": self.points_expected,
            "points_used": self.points_used,
            "residual_rms_cm": _json_number(self.residual_rms_cm),
            "residual_max_cm": _json_number(self.residual_max_cm),
            "loo_rms_cm": _json_number(self.loo_rms_cm),
            "loo_max_cm": _json_number(self.loo_max_cm),
            "loo": self.loo_kind,
            "coverage": self.coverage,
            "max_error_fraction": self.max_error_fraction,
            "max_range_m": self.max_range_m,
            "margin_m": self.margin_m,
            "near_field": self.near_field,
            "views": self.views,
            "intrinsics_given": self.intrinsics_given,
            "model_name": self.model_name,
            "model": self.model.to_dict(),
            "plausible_models": list(self.plausible),
            "error_inflation": _json_number(self.error_inflation),
            "noise_px": _json_number(self.noise_px),
            "predicted_error_by_range": [r.to_dict() for r in self.rings],
            "field_of_view": self.field_of_view.to_dict(),
        }

    def as_dict(self) -> Dict[str, Any]:
        """Everything, JSON-ready (NaN as null)."""

        num = _json_number
        d = self.metadata()
        d["image_size"] = list(self.image_size)
        d["spacing_px"] = self.spacing_px
        d["candidates"] = [{"model": n, "held_out_rms_px": num(e)} for n, e in self.candidates]
        d["notes"] = list(self.notes)
        d["timings_s"] = {k: round(v, 6) for k, v in self.timings_s.items()}
        d["points"] = [
            {
                "i": int(i),
                "j": int(j),
                "u_px": num(u),
                "v_px": num(v),
                "x_m": num(x),
                "y_m": num(y),
                "residual_cm": num(100 * r),
                "loo_cm": num(100 * e),
                "used": bool(ok),
            }
            for (i, j), (u, v), (x, y), r, e, ok in zip(
                self.indices,
                self.image_points,
                self.ground_points,
                self.residual_m,
                self.loo_m,
                self.used,
            )
        ]
        return d

    def save(self, path: PathLike) -> Path:
        """Writes :meth:`as_dict` as JSON, atomically."""
        return write_atomic(path, json.dumps(self.as_dict(), indent=1) + "\n")

    def __repr__(self) -> str:
        return f"CalibrationReport({self.summary()})"
