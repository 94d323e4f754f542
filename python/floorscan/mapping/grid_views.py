"""Read-only views of a grid shared by :class:`~floorscan.OccupancyGrid` and
:class:`~floorscan.LocalMap`: numpy arrays, images, obstacle queries.

Array layout follows ``nav_msgs/OccupancyGrid``: shape (H, W), ``[row, col] = [iy, ix]``, row 0 at
the lowest y (the extent's origin), x growing along a row. Images (PNG, PGM) are the same data
flipped so that row 0 is the top (highest y), as image viewers expect.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple, Union

import numpy as np

from .._atomic import PathLike, deferred_signals, discard_temporary, temp_path_for
from ..errors import LengthMismatchError, OptionError, OutOfBoundsError
from .log_odds import (  # noqa: F401 (OCCUPANCY_CLASSES, UNITS_PER_NAT re-exported)
    OCCUPANCY_CLASSES,
    UNITS_PER_NAT,
    Occupancy,
    probabilities_from_units,
)

IMAGE_STYLES = ("probability", "trinary")


@dataclass(frozen=True)
class GridExtent:
    """A rectangle of cells: its first (lower-left) cell ``(x_cell, y_cell)``, its size
    ``width`` x ``height`` [cells], and ``origin_m``, the world position [m] of its lower-left
    corner (the ``origin`` of a map_server map or a ``nav_msgs/OccupancyGrid``)."""

    x_cell: int
    y_cell: int
    width: int
    height: int
    cell_size_m: float
    origin_m: Tuple[float, float]

    @property
    def shape(self) -> Tuple[int, int]:
        """(H, W) of the arrays over this extent."""
        return (self.height, self.width)

    @property
    def bounds_m(self) -> Tuple[Tuple[float, float], Tuple[float, float]]:
        """((x_min, y_min), (x_max, y_max)) [m]."""
        x0, y0 = self.origin_m
        return (x0, y0), (x0 + self.width * self.cell_size_m, y0 + self.height * self.cell_size_m)


Coordinate = Union[float, np.ndarray]


MAX_CELL_INDEX = 1 << 30
"""Cells farther than this from the lattice origin do not exist (as in the Rust core)."""


def cell_index(name: str, value) -> int:
    """A cell coordinate as an int within +-2^30 (OutOfBoundsError otherwise)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise OutOfBoundsError(f"`{name}` must be an integer cell index, got {value!r}")
    if not -MAX_CELL_INDEX < int(value) < MAX_CELL_INDEX:
        raise OutOfBoundsError(f"`{name}` = {value} is more than 2^30 cells from the origin")
    return int(value)


def cell_count(name: str, value) -> int:
    """A rectangle side [cells] as a non-negative int (OutOfBoundsError otherwise)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or int(value) < 0:
        raise OutOfBoundsError(f"`{name}` must be a non-negative integer, got {value!r}")
    return min(int(value), 2 * MAX_CELL_INDEX)


def _xy(x, y) -> Tuple[np.ndarray, np.ndarray, bool]:
    xs = np.ascontiguousarray(np.atleast_1d(np.asarray(x, dtype=np.float64)).ravel())
    ys = np.ascontiguousarray(np.atleast_1d(np.asarray(y, dtype=np.float64)).ravel())
    if xs.shape != ys.shape:
        raise LengthMismatchError(f"x and y must have the same length, got {xs.size} and {ys.size}")
    return xs, ys, np.ndim(x) == 0 and np.ndim(y) == 0


class GridViews:
    """Mixin: needs ``self._native`` with ``extent``, ``values``, ``limits``,
    ``occupancy_codes``, ``distances``, ``cell_size_m`` and ``origin_m``."""

    _native: object

    @property
    def cell_size_m(self) -> float:
        """Side of a cell [m]."""
        return self._native.cell_size_m

    @property
    def extent(self) -> GridExtent:
        """The cells exported by default: a fixed-bounds map's bounds, a growing map's known
        cells (those with any evidence; the single cell at the lattice origin while there are
        none, so that an empty map still exports), a local map's window."""
        x, y, w, h = self._native.extent()
        if w == 0 or h == 0:
            x, y, w, h = 0, 0, 1, 1
        return self._extent(x, y, w, h)

    def _extent(self, x: int, y: int, w: int, h: int) -> GridExtent:
        s = self._native.cell_size_m
        ox, oy = self._native.origin_m
        return GridExtent(int(x), int(y), int(w), int(h), s, (ox + x * s, oy + y * s))

    def raw(self, extent: Optional[GridExtent] = None) -> np.ndarray:
        """(H, W) int16 log-odds in thousandths of a nat (0 = p 0.5 = no evidence)."""
        e = extent or self.extent
        if not isinstance(e, GridExtent):
            raise OutOfBoundsError(f"extent must be a GridExtent, got {type(e).__name__}")
        x, y = cell_index("x_cell", e.x_cell), cell_index("y_cell", e.y_cell)
        w, h = cell_count("width", e.width), cell_count("height", e.height)
        return self._native.values(x, y, w, h)

    def log_odds(self, extent: Optional[GridExtent] = None) -> np.ndarray:
        """(H, W) float32 log-odds [nats]."""
        return (self.raw(extent).astype(np.float32) / np.float32(UNITS_PER_NAT)).astype(np.float32)

    def probabilities(self, extent: Optional[GridExtent] = None) -> np.ndarray:
        """(H, W) float64 probability of occupancy, 0.5 where nothing is known."""
        return probabilities_from_units(self.raw(extent))

    def occupancy_classes(self, extent: Optional[GridExtent] = None) -> np.ndarray:
        """(H, W) uint8: 0 free, 1 unknown, 2 occupied (by the map's thresholds)."""
        raw = self.raw(extent)
        _, _, occupied_at, free_at = self._native.limits()
        out = np.full(raw.shape, Occupancy.UNKNOWN, np.uint8)
        out[raw <= free_at] = Occupancy.FREE
        out[raw >= occupied_at] = Occupancy.OCCUPIED
        return out

    def to_occupancy_msg(self, extent: Optional[GridExtent] = None) -> np.ndarray:
        """(H, W) int8 in ``nav_msgs/OccupancyGrid`` form: -1 where nothing is known (no
        evidence at all), else the probability of occupancy in percent, 0..100. Flatten it
        row-major for the message's ``data``; the extent's ``origin_m`` is its origin."""
        raw = self.raw(extent)
        p = probabilities_from_units(raw)
        out = np.clip(np.rint(p * 100.0), 0, 100).astype(np.int8)
        out[raw == 0] = -1
        return out

    def to_occupancy_grid(
        self, extent: Optional[GridExtent] = None
    ) -> Tuple[np.ndarray, float, Tuple[float, float, float]]:
        """``(data, resolution_m, origin)``: the fields of a ``nav_msgs/OccupancyGrid`` --
        :meth:`to_occupancy_msg` (H, W) int8, the cell size [m] and the origin pose
        ``(x, y, yaw)`` [m, m, rad] of cell [0, 0]'s lower-left corner."""
        e = extent or self.extent
        return self.to_occupancy_msg(e), e.cell_size_m, (e.origin_m[0], e.origin_m[1], 0.0)

    def to_image(
        self, *, style: str = "probability", extent: Optional[GridExtent] = None
    ) -> np.ndarray:
        """(H, W) uint8 picture, row 0 at the top (highest y). ``"probability"`` (the paper's
        look): grey level 255 * (1 - p), so occupied is dark, free light, unknown mid grey.
        ``"trinary"``: map_server colours (occupied 0, free 254, unknown 205)."""
        if style not in IMAGE_STYLES:
            raise OptionError(
                f"invalid option `style`: expected one of {IMAGE_STYLES}, got {style!r}"
            )
        raw = self.raw(extent)[::-1]
        # A lookup table over all int16 values: no float image in memory (large maps).
        return np.ascontiguousarray(self._lut(style)[raw.astype(np.int32) + 32768])

    def _lut(self, style: str) -> np.ndarray:
        units = np.arange(-32768, 32768, dtype=np.int32)
        if style == "probability":
            return np.rint(255.0 * (1.0 - probabilities_from_units(units))).astype(np.uint8)
        _, _, occupied_at, free_at = self._native.limits()
        lut = np.full(units.shape, 205, np.uint8)
        lut[units <= free_at] = 254
        lut[units >= occupied_at] = 0
        return lut

    def to_png(
        self,
        path: PathLike,
        *,
        scale: int = 1,
        style: str = "probability",
        extent: Optional[GridExtent] = None,
    ):
        """Writes :meth:`to_image` as a PNG (each cell ``scale`` x ``scale`` pixels),
        atomically; returns the path."""
        import os
        from pathlib import Path

        from PIL import Image

        if (
            isinstance(scale, bool)
            or not isinstance(scale, (int, np.integer))
            or not 1 <= scale <= 64
        ):
            raise OptionError(
                f"invalid option `scale`: must be an integer in 1..=64, got {scale!r}"
            )
        img = self.to_image(style=style, extent=extent)
        if img.size == 0:
            raise OptionError(
                "the map is empty: nothing to draw (insert data first or pass an extent)"
            )
        if scale > 1:
            img = np.repeat(np.repeat(img, scale, axis=0), scale, axis=1)
        tmp = None
        try:
            with deferred_signals():
                tmp = temp_path_for(path, ".png")
            Image.fromarray(img, mode="L").save(tmp, format="PNG", optimize=True)
            os.replace(tmp, path)
        except BaseException:
            if tmp is not None:
                discard_temporary(tmp)
            raise
        return Path(path)

    def is_free(self, x: Coordinate, y: Coordinate):
        """Whether the cell holding the point (x, y) [m] is free by the map's thresholds.
        Scalars give a bool, arrays a bool array."""
        xs, ys, scalar = _xy(x, y)
        free = self._native.occupancy_codes(xs, ys) == 0
        return bool(free[0]) if scalar else free

    def is_occupied(self, x: Coordinate, y: Coordinate):
        """Whether the cell holding the point (x, y) [m] is occupied."""
        xs, ys, scalar = _xy(x, y)
        occ = self._native.occupancy_codes(xs, ys) == 2
        return bool(occ[0]) if scalar else occ

    def distance_to_nearest_occupied(
        self, x: Coordinate, y: Coordinate, *, max_distance_m: float = 2.0
    ):
        """Distance [m] from the point (x, y) [m] to the nearest occupied cell (its nearest
        point; 0 inside one); ``inf`` if none lies within ``max_distance_m``. Scalars give a
        float, arrays an array."""
        xs, ys, scalar = _xy(x, y)
        d = self._native.distances(xs, ys, float(max_distance_m))
        return float(d[0]) if scalar else d
