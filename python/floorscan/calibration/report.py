"""What a calibration measured: the points found, how well the table reproduces each of them,
how well it predicts each when fitted without it, the model chosen, and the ground it covers."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Tuple

import numpy as np

from .._atomic import PathLike, write_atomic
from .model import RadialPlaneModel
from .pattern import Pattern
from .region import FieldOfView


def _rms(a: np.ndarray) -> float:
    a = np.asarray(a, float)
    return float(np.sqrt(np.mean(a * a))) if a.size else float("nan")


def _max(a: np.ndarray) -> float:
    return float(np.max(a)) if np.size(a) else float("nan")


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

    And: ``points_expected`` (the pattern's count), ``method`` (the detector), ``model`` (the
    fitted :class:`RadialPlaneModel`), ``model_name`` (its form, e.g. ``radial2+centre``),
    ``candidates`` (each model form tried and its
    leave-one-out RMS [px]), ``field_of_view`` (:class:`FieldOfView`), ``image_size`` (W, H),
    ``spacing_px``, ``extrapolate``, ``margin_m``, ``near_field``, ``pattern``, ``loo_kind`` (``refit`` or
    ``linearised``), ``timings_s`` (seconds per stage: detect, fit, table, leave_one_out,
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
    model: RadialPlaneModel
    model_name: str
    candidates: List[Tuple[str, float]]
    field_of_view: FieldOfView
    spacing_px: int
    extrapolate: bool
    margin_m: float
    near_field: bool = True
    loo_kind: str = "refit"
    timings_s: Dict[str, float] = field(default_factory=dict)
    notes: List[str] = field(default_factory=list)

    # --- figures ------------------------------------------------------------------------
    @property
    def points_found(self) -> int:
        return len(self.image_points)

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
            f"ground {near:.2f}..{far:.2f} m"
            f"{' (extrapolated)' if self.extrapolate else ''}; model {self.model_name}"
        )

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
            "extrapolate": self.extrapolate,
            "margin_m": self.margin_m,
            "near_field": self.near_field,
            "model_name": self.model_name,
            "model": self.model.to_dict(),
            "field_of_view": self.field_of_view.to_dict(),
        }

    def as_dict(self) -> Dict[str, Any]:
        """Everything, JSON-ready (NaN as null)."""

        num = _json_number
        d = self.metadata()
        d["image_size"] = list(self.image_size)
        d["spacing_px"] = self.spacing_px
        d["candidates"] = [{"model": n, "loo_rms_px": num(e)} for n, e in self.candidates]
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
