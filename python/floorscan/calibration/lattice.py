"""A detected lattice of pattern points matched to the pattern (i across, j away) from
geometry alone: the pattern's away axis runs up the image and its across axis left to right
(both turned by the pattern's yaw), so a detection that comes out flipped or rotated cannot mirror
the table. Shared by the checkerboard detector (:mod:`.detect`) and the line-grid detector
(:mod:`.lines`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from ..errors import CalibrationError
from .pattern import Pattern

MIN_AXIS_AGREEMENT = 0.3
"""Least mean cosine between a detected lattice axis and its expected image direction (the
pattern's axes may turn by up to about 70 degrees in the image before the match is refused)."""


@dataclass(frozen=True)
class Detection:
    """Pattern points found in an image, matched to the pattern.

    - ``image_points``: (M, 2) float64 [px], (u, v), v counted from the top.
    - ``ground_points``: (M, 2) float64 [m], the same points on the floor (camera ground frame).
    - ``indices``: (M, 2) int, the pattern coordinates (i across, j away) of each point.
    - ``method``: which detector found them.
    """

    image_points: np.ndarray
    ground_points: np.ndarray
    indices: np.ndarray
    method: str

    @property
    def count(self) -> int:
        return len(self.image_points)


def expected_image_axes(yaw: float) -> Tuple[np.ndarray, np.ndarray]:
    """Rough image directions (du, dv) of the pattern's across and away axes for a camera
    looking forward over the floor: ground +x runs up the image, ground +y to the left."""
    across = np.array([math.cos(yaw), -math.sin(yaw)])
    away = np.array([-math.sin(yaw), -math.cos(yaw)])
    return across, away


def _mean_direction(a: np.ndarray, axis: int) -> np.ndarray:
    d = np.diff(a, axis=axis).reshape(-1, 2)
    d = d[np.all(np.isfinite(d), axis=1)]
    if len(d) == 0:
        return np.zeros(2)
    n = np.linalg.norm(d, axis=1, keepdims=True)
    return np.mean(d / np.maximum(n, 1e-12), axis=0)


def lattice_orientations(
    lattice: np.ndarray, counts: Tuple[int, int], *, partial_away: bool = False
) -> List[np.ndarray]:
    """Every flip / rotation of ``lattice`` ((rows, cols, 2)) with the pattern's shape
    (counts[1] rows away, counts[0] columns across). With ``partial_away``, also those with
    every column but fewer rows, padded with NaN rows on the far side."""
    out = []
    for t in (False, True):
        a = lattice.transpose(1, 0, 2) if t else lattice
        rows, cols = a.shape[:2]
        if cols != counts[0] or not (rows == counts[1] or (partial_away and rows < counts[1])):
            continue
        for fr in (False, True):
            for fc in (False, True):
                b = a[::-1] if fr else a
                b = b[:, ::-1] if fc else b
                if rows < counts[1]:
                    pad = np.full((counts[1] - rows, cols, 2), np.nan)
                    b = np.concatenate([b, pad], axis=0)
                out.append(np.ascontiguousarray(b))
    return out


def label_lattice(
    lattice: np.ndarray, pattern: Pattern, method: str, *, partial_away: bool = False
) -> Detection:
    """Chooses the flip / rotation of a detected lattice (rows, cols, 2; NaN where a point is
    missing) whose axes best agree with the pattern's expected image directions, and pairs
    its points with their ground positions. ``partial_away`` accepts a lattice missing rows,
    taken as the farthest ones (the caller has checked that the nearest row is the
    pattern's)."""
    candidates = lattice_orientations(lattice, pattern.counts, partial_away=partial_away)
    if not candidates:
        raise CalibrationError(
            f"found a grid of {lattice.shape[1]} x {lattice.shape[0]} points, but the pattern "
            f"has {pattern.counts[0]} x {pattern.counts[1]}: check the counts in the pattern file"
        )
    across, away = expected_image_axes(pattern.yaw)

    def score(a: np.ndarray) -> float:
        return float(_mean_direction(a, 1) @ across + _mean_direction(a, 0) @ away)

    best = max(candidates, key=score)
    along_across = float(_mean_direction(best, 1) @ across)
    along_away = float(_mean_direction(best, 0) @ away)
    if min(along_across, along_away) < MIN_AXIS_AGREEMENT:
        raise CalibrationError(
            f"the grid of points found does not run as the pattern file says: its "
            f"{pattern.counts[0]}-point rows should run left to right in the image and its "
            f"{pattern.counts[1]}-point columns away from the camera (turned by `yaw` = "
            f"{pattern.yaw:g} rad); check the order of the counts and `yaw`"
        )
    j, i = np.mgrid[0 : pattern.counts[1], 0 : pattern.counts[0]]
    pts = best.reshape(-1, 2)
    keep = np.all(np.isfinite(pts), axis=1)
    idx = np.column_stack([i.ravel(), j.ravel()])[keep]
    return Detection(
        image_points=pts[keep].copy(),
        ground_points=pattern.ground_of(idx[:, 0], idx[:, 1]),
        indices=idx,
        method=method,
    )


def min_neighbour_distance(points: np.ndarray) -> Optional[float]:
    """Smallest distance between two of ``points`` (N, 2), None for fewer than two."""
    if len(points) < 2:
        return None
    d = np.linalg.norm(points[:, None] - points[None], axis=-1)
    d[np.diag_indices(len(points))] = np.inf
    return float(d.min())
