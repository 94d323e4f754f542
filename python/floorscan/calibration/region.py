"""The pattern's calibrated region (the detected points plus a margin: ``coverage =
"pattern"``), the table's node grid, and the field of view a finished table covers."""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Tuple

import cv2
import numpy as np

from ..ranging.ground_table import GroundTable


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Convex hull of (N, 2) points, counter-clockwise in a y-up frame: (K, 2)."""
    hull = cv2.convexHull(np.asarray(points, np.float64).astype(np.float32)).reshape(-1, 2)
    hull = hull.astype(np.float64)
    area = 0.5 * np.sum(hull[:, 0] * np.roll(hull[:, 1], -1) - np.roll(hull[:, 0], -1) * hull[:, 1])
    return hull if area >= 0 else hull[::-1]


def distance_outside(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Distance [same units] from each of ``points`` (..., 2) to a convex counter-clockwise
    ``polygon`` (K, 2); 0 inside it."""
    p = np.asarray(points, np.float64)
    shape = p.shape[:-1]
    p = p.reshape(-1, 2)
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    ab = b - a
    ap = p[:, None, :] - a[None]
    t = np.clip(np.sum(ap * ab, -1) / np.maximum(np.sum(ab * ab, -1), 1e-30), 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    d = np.min(np.linalg.norm(p[:, None, :] - closest, axis=-1), axis=1)
    cross = ab[None, :, 0] * ap[..., 1] - ab[None, :, 1] * ap[..., 0]
    inside = np.all(cross >= 0, axis=1)
    return np.where(inside, 0.0, d).reshape(shape)


def node_grid(image_size: Tuple[int, int], spacing_px: int) -> Tuple[np.ndarray, np.ndarray]:
    """Pixel coordinates (u, v) of a table's nodes: two (nodes_v, nodes_u) arrays [px]."""
    nu, nv = GroundTable.node_shape_for(
        image_width=image_size[0], image_height=image_size[1], spacing_px=spacing_px
    )
    v, u = np.mgrid[0:nv, 0:nu].astype(np.float64) * spacing_px
    return u, v


GROWTH_LIMIT = 2.0
"""The nodes added around the region reach at most this many margins from it."""


def near_region(x: np.ndarray, y: np.ndarray, region: np.ndarray, margin_m: float) -> np.ndarray:
    """Nodes ((nodes_v, nodes_u) ground arrays [m]) within ``margin_m`` [m] of the ground
    polygon ``region``, grown by one node in the image, so that every pixel inside the region
    has its four surrounding nodes; but no node farther than ``GROWTH_LIMIT`` margins from the
    region (far away, one node spans more floor than the margin: with 8 px nodes a full ring
    reached 30 cm past a line grid's far row and 1.2-1.4 cm errors, bench/calibration.py)."""
    d = distance_outside(np.stack([np.nan_to_num(x), np.nan_to_num(y)], -1), region)
    near = (d <= margin_m) & np.isfinite(x)
    grown = cv2.dilate(near.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    return grown & np.isfinite(x) & (d <= GROWTH_LIMIT * margin_m)


@dataclass(frozen=True)
class FieldOfView:
    """The ground a table covers.

    - ``polygon_m``: (K, 2) [m] outline of the covered ground (camera ground frame), traced
      along the table's outermost valid nodes, counter-clockwise.
    - ``columns_px``: (N,) image columns u [px] (the table's node columns).
    - ``near_range_m``, ``far_range_m``: (N,) [m] nearest and farthest ground range seen in
      each of those columns; NaN where a column sees no ground.
    """

    polygon_m: np.ndarray
    columns_px: np.ndarray
    near_range_m: np.ndarray
    far_range_m: np.ndarray

    @property
    def range_m(self) -> Tuple[float, float]:
        """Nearest and farthest ground range over all columns [m] (NaN if none)."""
        if not np.any(np.isfinite(self.near_range_m)):
            return float("nan"), float("nan")
        return float(np.nanmin(self.near_range_m)), float(np.nanmax(self.far_range_m))

    def to_dict(self) -> dict:
        def clean(a: np.ndarray) -> List[Optional[float]]:
            return [None if not np.isfinite(x) else round(float(x), 5) for x in a]

        return {
            "polygon_m": [[round(float(x), 5), round(float(y), 5)] for x, y in self.polygon_m],
            "columns_px": [int(u) for u in self.columns_px],
            "near_range_m": clean(self.near_range_m),
            "far_range_m": clean(self.far_range_m),
        }


def field_of_view(table: GroundTable) -> FieldOfView:
    """What ``table`` covers: its ground outline and, per node column, near and far range."""
    x, y = table.nodes
    ok = np.isfinite(x)
    s = table.spacing_px
    rng = np.where(ok, np.hypot(x, y), np.nan)
    any_col = np.any(ok, axis=0)
    with np.errstate(all="ignore"):
        near = np.where(any_col, np.nanmin(np.where(ok, rng, np.inf), axis=0), np.nan)
        far = np.where(any_col, np.nanmax(np.where(ok, rng, -np.inf), axis=0), np.nan)
    columns = np.arange(x.shape[1]) * s
    polygon = np.zeros((0, 2))
    if np.any(ok):
        contours, _ = cv2.findContours(
            ok.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE
        )
        c = max(contours, key=len).reshape(-1, 2)  # (i, j) node indices
        polygon = np.column_stack([x[c[:, 1], c[:, 0]], y[c[:, 1], c[:, 0]]])
        area = 0.5 * np.sum(
            polygon[:, 0] * np.roll(polygon[:, 1], -1) - np.roll(polygon[:, 0], -1) * polygon[:, 1]
        )
        if area < 0:
            polygon = polygon[::-1]
    return FieldOfView(polygon, columns, near, far)
