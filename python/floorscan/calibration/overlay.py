"""The calibration picture of the paper's Fig. 1c: the pattern as the table sees it, drawn over
the calibration image. Every pixel is looked up in the table; the pattern's lines are where the
looked-up ground point crosses a line of the pattern, so any error of the table shows as a line
off the real one."""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional, Union

import cv2
import numpy as np

from ..errors import ImageError
from ..ranging.ground_table import GroundTable
from .detect import to_uint8
from .pattern import Pattern, PatternKind

if TYPE_CHECKING:  # pragma: no cover
    from .report import CalibrationReport

LINE_COLOUR = (40, 255, 40)  # the estimated pattern
POINT_COLOUR = (255, 40, 40)  # the detected points
NO_GROUND_TINT = np.array([40, 60, 160], float)  # where the table has no ground
UNTRUSTED_TINT = np.array([230, 120, 20], float)  # floor the model sees but does not trust
RING_COLOUR = (255, 230, 40)  # range rings
RING_STEP_M = 0.5


def draw_calibration_overlay(
    image: np.ndarray,
    table: GroundTable,
    pattern: Union[Pattern, CalibrationReport],
    *,
    points: Optional[np.ndarray] = None,
    thickness_px: int = 1,
) -> np.ndarray:
    """An RGB (H, W, 3) uint8 picture: ``image`` with the estimated pattern (its lines,
    computed from ``table``) in green, ``points`` ((M, 2) [px]; by default the detected points
    when ``pattern`` is a :class:`CalibrationReport`) as red circles, range rings every
    ``RING_STEP_M`` [m] in yellow, the pixels where the table has no ground tinted blue, and,
    given the report, the floor its camera model sees within the maximum range but does not
    trust (predicted error above the bound) tinted orange. ``pattern``: a :class:`Pattern`,
    or the report of the calibration that made ``table``."""
    model_floor = None
    report = None
    if not isinstance(pattern, Pattern):
        report = pattern
        if points is None:
            points = pattern.image_points
        pattern = pattern.pattern
    grey = to_uint8(image)
    h, w = grey.shape
    if (w, h) != (table.image_width, table.image_height):
        raise ImageError(
            f"image is {w} x {h} but the table is for {table.image_width} x {table.image_height}"
        )
    v, u = np.mgrid[0:h, 0:w].astype(np.float64)
    x, y = table.lookup(u, v)
    across, away = pattern.axes()
    dx, dy = x - pattern.near_left[0], y - pattern.near_left[1]
    i = (dx * across[0] + dy * across[1]) / pattern.step_m
    j = (dx * away[0] + dy * away[1]) / pattern.step_m
    n_i, n_j = pattern.counts
    if pattern.kind is PatternKind.CHECKERBOARD:
        # The board's square edges: lines i, j = -1 .. n, across the whole board.
        lo_i, hi_i, lo_j, hi_j = -1.0, float(n_i), -1.0, float(n_j)
        pad = 0.0
    else:
        # The lines: i, j = 0 .. n - 1, overhanging by half a spacing.
        lo_i, hi_i, lo_j, hi_j = 0.0, n_i - 1.0, 0.0, n_j - 1.0
        pad = 0.5
    mask = _crossings(i, lo_i, hi_i, j, lo_j - pad, hi_j + pad)
    mask |= _crossings(j, lo_j, hi_j, i, lo_i - pad, hi_i + pad)
    if thickness_px > 1:
        mask = (
            cv2.dilate(mask.astype(np.uint8), np.ones((thickness_px, thickness_px), np.uint8)) > 0
        )
    rgb = np.repeat(grey[..., None], 3, axis=2).astype(np.float64)
    no_ground = ~np.isfinite(x)
    if report is not None:
        mx, my = report.model.ground(u, v)
        c = report.model.centre_m
        model_floor = np.isfinite(mx) & (np.hypot(mx - c[0], my - c[1]) <= report.max_range_m)
    untrusted = no_ground & model_floor if model_floor is not None else np.zeros_like(no_ground)
    rgb[no_ground & ~untrusted] = 0.6 * rgb[no_ground & ~untrusted] + 0.4 * NO_GROUND_TINT
    rgb[untrusted] = 0.6 * rgb[untrusted] + 0.4 * UNTRUSTED_TINT
    out = np.clip(rgb, 0, 255).astype(np.uint8)
    rings = np.hypot(x, y) / RING_STEP_M
    ring_mask = _crossings(rings, 1, 1e9, rings, 0, 1e9)
    out[ring_mask] = RING_COLOUR
    out[mask] = LINE_COLOUR
    if points is not None:
        radius = max(2, round(min(w, h) / 160))
        for pu, pv in np.asarray(points, float).reshape(-1, 2):
            if np.isfinite(pu) and np.isfinite(pv):
                cv2.circle(
                    out,
                    (int(round(pu * 4)), int(round(pv * 4))),
                    radius * 4,
                    POINT_COLOUR,
                    1,
                    cv2.LINE_AA,
                    shift=2,
                )
    return out


def _crossings(
    f: np.ndarray, lo: float, hi: float, other: np.ndarray, other_lo: float, other_hi: float
) -> np.ndarray:
    """Pixels where the field ``f`` crosses an integer in [lo, hi] (to the next pixel right or
    down) while ``other`` lies in [other_lo, other_hi]."""
    mask = np.zeros(f.shape, bool)
    with np.errstate(invalid="ignore"):
        k = np.floor(f)
        inside = (other >= other_lo) & (other <= other_hi)
        for a, b, sl_a, sl_b in (
            (k[:, :-1], k[:, 1:], np.s_[:, :-1], np.s_[:, 1:]),
            (k[:-1], k[1:], np.s_[:-1], np.s_[1:]),
        ):
            n = np.maximum(a, b)
            hit = (a != b) & np.isfinite(a) & np.isfinite(b) & (n >= lo) & (n <= hi)
            hit &= inside[sl_a] & inside[sl_b]
            mask[sl_a] |= hit
    return mask
