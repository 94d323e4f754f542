"""The true occupancy raster of a world, and a small, self-contained map_server writer (YAML +
PGM, trinary: occupied 0 black, free 254, unknown 205)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Tuple

import numpy as np

from .._atomic import PathLike
from ..formats.map_server import write_map_files

OCCUPIED = 100
FREE = 0
UNKNOWN = -1


@dataclass(frozen=True)
class OccupancyRaster:
    """Cells as in nav_msgs/OccupancyGrid: ``cells`` (H, W) int8 with 100 occupied, 0 free,
    -1 unknown; row 0 is the lowest y. ``origin`` (x, y) [m] is the world position of the
    lower-left corner of cell (0, 0); ``resolution_m`` [m/cell]."""

    cells: np.ndarray
    origin: Tuple[float, float]
    resolution_m: float

    def value_at(self, x: float, y: float) -> int:
        """The cell value at a world point [m] (UNKNOWN outside)."""
        i = int(np.floor((x - self.origin[0]) / self.resolution_m))
        j = int(np.floor((y - self.origin[1]) / self.resolution_m))
        h, w = self.cells.shape
        if 0 <= i < w and 0 <= j < h:
            return int(self.cells[j, i])
        return UNKNOWN

    def to_pgm_image(self) -> np.ndarray:
        """The map_server image: (H, W) uint8, top row = highest y, occupied 0, free 254,
        unknown 205."""
        img = np.full(self.cells.shape, 205, dtype=np.uint8)
        img[self.cells == OCCUPIED] = 0
        img[self.cells == FREE] = 254
        return np.ascontiguousarray(img[::-1])

    def write_map_server(self, yaml_path: PathLike) -> Path:
        """Writes ``<name>.yaml`` and ``<name>.pgm`` beside it (map_server format, trinary),
        atomically. Returns the YAML path."""
        return write_map_files(
            yaml_path, self.to_pgm_image(), cell_size_m=self.resolution_m, origin_m=self.origin
        )
