"""Checking a ground table on another image of a pattern, without refitting: each detected
point's floor error through the table, by range, and (for tables with predicted errors) how many
points the table's own error bars cover."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List, Union

import numpy as np

from .._atomic import PathLike
from ..errors import ImageError
from ..ranging.ground_table import GroundTable
from .detect import detect, to_uint8
from .pattern import Pattern
from .report import RING_STEP_M, _json_number


@dataclass
class TableCheck:
    """Per detected point (M): ``image_points`` (M, 2) [px], ``ground_points`` (M, 2) [m] (the
    pattern's), ``error_m`` (M,) [m] distance between the table's floor point and the
    pattern's (NaN where the table has no ground), ``predicted_m`` (M,) the table's predicted
    error there (NaN without one), ``range_m`` (M,) the pattern point's range."""

    image_points: np.ndarray
    ground_points: np.ndarray
    indices: np.ndarray
    error_m: np.ndarray
    predicted_m: np.ndarray
    range_m: np.ndarray

    @property
    def covered(self) -> np.ndarray:
        return np.isfinite(self.error_m)

    @property
    def within_bars(self) -> float:
        """Share of the covered points whose error is at most the predicted error (NaN when
        the table predicts none)."""
        ok = self.covered & np.isfinite(self.predicted_m)
        if not ok.any():
            return float("nan")
        return float(np.mean(self.error_m[ok] <= self.predicted_m[ok]))

    def by_range(self) -> List[Dict[str, Any]]:
        """Per ``RING_STEP_M`` ring: points, covered, RMS and max error [cm]."""
        out = []
        if not len(self.range_m):
            return out
        top = float(np.ceil(np.nanmax(self.range_m) / RING_STEP_M) * RING_STEP_M)
        for lo in np.arange(0.0, top, RING_STEP_M):
            m = (self.range_m >= lo) & (self.range_m < lo + RING_STEP_M)
            if not m.any():
                continue
            e = self.error_m[m & self.covered]
            out.append(
                {
                    "near_m": float(lo),
                    "far_m": float(lo + RING_STEP_M),
                    "points": int(m.sum()),
                    "covered": int(e.size),
                    "rms_cm": _json_number(100 * np.sqrt(np.mean(e**2))) if e.size else None,
                    "max_cm": _json_number(100 * e.max()) if e.size else None,
                }
            )
        return out

    def summary(self) -> str:
        e = self.error_m[self.covered]
        n = len(self.error_m)
        head = f"{int(self.covered.sum())}/{n} points covered by the table"
        if not e.size:
            return head
        text = (
            f"{head}; error RMS {100 * np.sqrt(np.mean(e**2)):.2f} cm, max {100 * e.max():.2f} cm "
            f"over {np.nanmin(self.range_m):.2f}..{np.nanmax(self.range_m):.2f} m"
        )
        if np.isfinite(self.within_bars):
            text += f"; {100 * self.within_bars:.0f} % within the table's predicted error"
        return text

    def as_dict(self) -> Dict[str, Any]:
        num = _json_number
        return {
            "summary": self.summary(),
            "within_predicted": num(self.within_bars),
            "by_range": self.by_range(),
            "points": [
                {
                    "i": int(i),
                    "j": int(j),
                    "u_px": num(u),
                    "v_px": num(v),
                    "range_m": num(r),
                    "error_cm": num(100 * e),
                    "predicted_cm": num(100 * p),
                }
                for (i, j), (u, v), r, e, p in zip(
                    self.indices, self.image_points, self.range_m, self.error_m, self.predicted_m
                )
            ],
        }


def check_table(
    table: GroundTable, image: np.ndarray, pattern: Union[Pattern, PathLike]
) -> TableCheck:
    """Scores ``table`` on ``image`` of ``pattern`` (detected, not refitted).

    Raises:
        floorscan.CalibrationError: the pattern is not found.
        floorscan.ImageError: the image is not the table's size.
    """
    pattern = Pattern.resolve(pattern)
    grey = to_uint8(image)
    h, w = grey.shape
    if (w, h) != (table.image_width, table.image_height):
        raise ImageError(
            f"image is {w} x {h} but the table is for {table.image_width} x {table.image_height}"
        )
    det = detect(grey, pattern)
    uv, g = det.image_points, det.ground_points
    x, y = table.lookup(uv[:, 0], uv[:, 1])
    err = np.hypot(x - g[:, 0], y - g[:, 1])
    pred = (
        table.lookup_error(uv[:, 0], uv[:, 1])
        if table.error_m is not None
        else np.full(len(uv), np.nan)
    )
    return TableCheck(uv, g, det.indices, err, np.asarray(pred, float), np.hypot(g[:, 0], g[:, 1]))
