"""The true occupancy raster of a world, and a small, self-contained map_server writer (YAML +
PGM, trinary: occupied 0 black, free 254, unknown 205)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Tuple

import numpy as np

from .._atomic import PathLike, write_atomic

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
        yaml_path = Path(yaml_path)
        pgm_path = yaml_path.with_suffix(".pgm")
        img = self.to_pgm_image()
        h, w = img.shape
        write_atomic(pgm_path, f"P5\n{w} {h}\n255\n".encode("ascii") + img.tobytes())
        text = (
            f"image: {pgm_path.name}\n"
            "mode: trinary\n"
            f"resolution: {self.resolution_m:.6g}\n"
            f"origin: [{self.origin[0]:.6g}, {self.origin[1]:.6g}, 0.0]\n"
            "negate: 0\n"
            "occupied_thresh: 0.65\n"
            "free_thresh: 0.196\n"
        )
        return write_atomic(yaml_path, text)
