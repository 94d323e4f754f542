"""Simulated worlds: floor plans with walls, boxes, overhanging tables, chairs, floor coverings
(carpet, linoleum, tiles, paper scraps) and lighting. World frame: REP 103 (x, y on the floor,
z up), metres. The world file format (TOML) is documented in docs/simulator.md."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional, Tuple

import numpy as np

from .._atomic import PathLike
from .._native import sim as _native
from ..errors import WorldError
from .occupancy import OccupancyRaster


class World:
    """A world, loaded from a file or built in.

    >>> w = World.builtin("room")
    >>> w.name, w.start
    ('room', (0.65, 0.5, 0.0))
    >>> sorted(World.builtin_names())
    ['corridor', 'lab', 'parquet', 'patterned', 'room', 'tiles']
    """

    __slots__ = ("_native",)

    def __init__(self, native: _native.SimWorld) -> None:
        self._native = native

    @classmethod
    def load(cls, path: PathLike) -> World:
        """Reads a world file (TOML). Errors raise :class:`~floorscan.WorldError` naming the
        line (syntax, types) or the field (values)."""
        try:
            text = Path(path).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise WorldError(f"cannot read world file {path}: {e}") from None
        return cls(_native.SimWorld.from_toml(text, str(path)))._start_in_free_space(str(path))

    @classmethod
    def from_toml(cls, text: str, *, source_name: str = "<string>") -> World:
        """Parses world file text; ``source_name`` prefixes error messages."""
        return cls(_native.SimWorld.from_toml(text, source_name))._start_in_free_space(source_name)

    START_CHECK_RESOLUTION_M = 0.02
    """Cell of the raster the start pose is checked on [m]."""

    def _start_in_free_space(self, source: str) -> World:
        """This world, if its start pose lies in free floor: a start inside a wall or an
        obstacle would "simulate" a robot stuck in it (WorldError naming the file)."""
        r = self.occupancy(resolution_m=self.START_CHECK_RESOLUTION_M)
        x, y, _ = self.start
        i = int(np.floor((x - r.origin[0]) / r.resolution_m))
        j = int(np.floor((y - r.origin[1]) / r.resolution_m))
        inside = 0 <= j < r.cells.shape[0] and 0 <= i < r.cells.shape[1]
        if not inside or r.cells[j, i] != 0:
            raise WorldError(
                f"{source}: the start pose ({x:g}, {y:g}) lies inside a wall or an obstacle, "
                "not on free floor: move [start]"
            )
        return self

    @classmethod
    def builtin(cls, name: str) -> World:
        """A built-in world: ``corridor``, ``room``, ``lab`` or ``tiles``."""
        return cls(_native.SimWorld.builtin(name))

    @staticmethod
    def builtin_names() -> List[str]:
        return list(_native.SimWorld.builtin_names())

    @classmethod
    def resolve(cls, name_or_path: PathLike) -> World:
        """A built-in world if ``name_or_path`` names one, else the world file at that path; a
        name that is neither is a WorldError listing the built-in worlds."""
        names = cls.builtin_names()
        if str(name_or_path) in names:
            return cls.builtin(str(name_or_path))
        if not Path(name_or_path).exists():
            raise WorldError(
                f"unknown world {str(name_or_path)!r}: not a built-in world "
                f"({', '.join(names)}) nor a world file"
            )
        return cls.load(name_or_path)

    @property
    def name(self) -> str:
        return self._native.name

    @property
    def description(self) -> str:
        return self._native.description

    @property
    def source(self) -> Optional[str]:
        """The world file's text (None for worlds not read from a file)."""
        return self._native.source

    @property
    def ceiling_m(self) -> float:
        return self._native.ceiling_m

    @property
    def start(self) -> Tuple[float, float, float]:
        """Start pose of the robot base (x [m], y [m], yaw [rad]), world frame."""
        return tuple(self._native.start)

    @property
    def tour(self) -> np.ndarray:
        """Default waypoint tour, (K, 2) [m], world frame; driven in order and repeated."""
        return np.array(self._native.tour, dtype=np.float64).reshape(-1, 2)

    @property
    def bounds(self) -> Tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) [m] of everything in the world."""
        return tuple(self._native.bounds)

    def occupancy(
        self, *, resolution_m: float = 0.05, robot_height_m: float = 0.5, margin_m: float = 0.5
    ) -> OccupancyRaster:
        """The true occupancy raster at any resolution [m/cell]. Solids whose base is at or
        above ``robot_height_m`` [m] (table tops) do not block; free space is what the start
        reaches; the rest is unknown. ``margin_m`` [m] pads the world's bounds."""
        import json

        opts = {
            "resolution_m": float(resolution_m),
            "robot_height_m": float(robot_height_m),
            "margin_m": float(margin_m),
        }
        cells, ox, oy = self._native.occupancy(json.dumps(opts))
        return OccupancyRaster(cells=cells, origin=(ox, oy), resolution_m=float(resolution_m))

    def __repr__(self) -> str:
        return f"World({self.name!r})"
