"""The global occupancy grid (paper IV): log-odds cells fed by visual scans, laser scans and
sonar readings, each with its own evidence, with the once-per-scan rule (within one scan a
cell changes at most once, and occupied wins over free).

Frames: poses are ``world_from_robot`` ``(x [m], y [m], yaw [rad])``; mounts are
``robot_from_sensor`` in the same form (REP 103: x forward, y left, yaw counter-clockwise).
"""

from __future__ import annotations

from typing import Any, Dict, NamedTuple, Optional

import numpy as np

from .._atomic import PathLike
from .._native import mapping as _native
from ..errors import ArgumentTypeError, LengthMismatchError, OptionError
from ..formats.map_server import pixels_to_units, read_map_image, read_map_yaml, save_map
from ..ranging.scan import Scan
from .evidence import EvidenceMap
from .grid_options import EvidenceLike, as_evidence, as_pose, as_poses, split_options
from .grid_views import GridViews, cell_index


class InsertStats(NamedTuple):
    """What an insert did: rays walked, cells visited (counting repeats), cells marked."""

    rays: int
    cells_traversed: int
    cells_hit: int


def laser_args(ranges, angles, angle_min, angle_increment, *, two_d: bool = False):
    """Checks a laser layout: explicit ``angles`` [rad], or ``angle_min`` and
    ``angle_increment`` [rad] (the ``sensor_msgs/LaserScan`` fields)."""
    r = np.ascontiguousarray(ranges, dtype=np.float64)
    if r.ndim != (2 if two_d else 1):
        shape = "(N, B) (scans, beams)" if two_d else "(B,)"
        raise LengthMismatchError(f"`ranges` must have shape {shape}, got {r.shape}")
    if angles is not None:
        if angle_min is not None or angle_increment is not None:
            raise ArgumentTypeError(
                "give either `angles` or `angle_min` and `angle_increment`, not both"
            )
        a = np.ascontiguousarray(angles, dtype=np.float64)
        if a.ndim != 1 or a.size != r.shape[-1]:
            raise LengthMismatchError(f"{r.shape[-1]} ranges per scan but {a.size} angles")
        return r, a, 0.0, 0.0
    if angle_min is None or angle_increment is None:
        raise ArgumentTypeError("give `angles`, or both `angle_min` and `angle_increment`")
    return r, None, float(angle_min), float(angle_increment)


def sonar_args(ranges, mounts):
    """(K,) ranges and (K, 3) mounts; a single mount (3,) serves every reading."""
    r = np.ascontiguousarray(np.atleast_1d(np.asarray(ranges, dtype=np.float64)))
    m = np.asarray(mounts, dtype=np.float64)
    if m.shape == (3,):
        m = np.tile(m, (r.size, 1))
    m = np.ascontiguousarray(m)
    if r.ndim != 1 or m.shape != (r.size, 3):
        raise LengthMismatchError(
            f"{r.size} sonar ranges need {r.size} mounts (x, y, yaw), got shape {np.shape(mounts)}"
        )
    return r, m


class OccupancyGrid(GridViews):
    """A global occupancy grid: fixed to the world, growing as the robot explores (tiles of
    128 x 128 cells allocated on demand, 2 bytes per cell), or with fixed bounds.

    Parameters (all keyword-only):
        keep_evidence: also keep, per cell, the unclamped sum of every increment (int32, 4
            more bytes per cell), for exact merges of maps (:meth:`evidence`,
            :mod:`floorscan.mapping.evidence`). Off unless given.
        **options: any field of the core's ``GridOptions`` (``cell_size_m``, ``origin_m``,
            ``bounds_m`` for a fixed-size map (rays clipped to it, a pose outside it raises
            OutOfBoundsError; unset: the map grows), ``clamp_min_nats``, ``clamp_max_nats``,
            ``occupied_threshold``, ``free_threshold``, ``max_cells`` (a pose far outside
            raises OutOfBoundsError instead of allocating, docs/limits.md)) or
            ``InserterOptions`` (``visual``, ``laser``, ``sonar``: :class:`~floorscan.Evidence`
            or ``(hit_nats, miss_nats)``; ``too_close``: ``"mark_near_edge"`` or ``"ignore"``;
            ``boundary_margin_rows``). The others take the Rust defaults, printed with their
            docs by ``floorscan config --default`` (tables ``[grid]`` and ``[sensors]``).

    >>> import floorscan, numpy as np
    >>> grid = floorscan.OccupancyGrid(cell_size_m=0.1)
    >>> grid.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0.05, 0.05, 0.0))
    InsertStats(rays=1, cells_traversed=11, cells_hit=1)
    >>> grid.is_occupied(1.05, 0.05), grid.is_free(0.5, 0.05)
    (True, False)
    """

    def __init__(self, *, keep_evidence: bool = False, **options: Any) -> None:
        go, io = split_options(options)
        self._native = _native.OccupancyGrid(go, io)
        if keep_evidence:
            self._native.keep_evidence()

    @classmethod
    def _wrap(cls, native) -> OccupancyGrid:
        g = cls.__new__(cls)
        g._native = native
        return g

    def copy(self) -> OccupancyGrid:
        """An independent copy."""
        return OccupancyGrid._wrap(self._native.copy())

    @property
    def options(self) -> Dict[str, Any]:
        """The validated grid and inserter options (the core's serde form)."""
        return {
            "grid": self._native.grid_options,
            "inserter": self._native.inserter_options,
        }

    @property
    def memory_bytes(self) -> int:
        """Bytes held: cells, tile directory and the inserter's scratch memory."""
        return self._native.memory_bytes

    @property
    def allocated_tiles(self) -> int:
        """Tiles of 128 x 128 cells allocated so far."""
        return self._native.allocated_tiles

    def insert_scan(self, scan: Scan, pose, mount=(0.0, 0.0, 0.0)) -> InsertStats:
        """Inserts one visual :class:`~floorscan.Scan` (points in the camera ground frame)
        seen from ``pose`` (``world_from_robot``), the camera at ``mount``
        (``robot_from_camera``: x, y, yaw of the camera ground frame on the robot, as in a
        dataset's rig.toml ``[camera]``). Free space starts at each column's near edge of view;
        see :mod:`floorscan.mapping.grid` for the rules. The GIL is released."""
        if not isinstance(scan, Scan):
            raise ArgumentTypeError(f"scan must be a floorscan.Scan, got {type(scan).__name__}")
        return InsertStats(
            *self._native.insert_scan(scan._native, as_pose(pose, "pose"), as_pose(mount, "mount"))
        )

    def insert_laser(
        self,
        ranges,
        *,
        pose,
        range_max_m: float,
        range_min_m: float = 0.0,
        angles=None,
        angle_min: Optional[float] = None,
        angle_increment: Optional[float] = None,
        mount=(0.0, 0.0, 0.0),
    ) -> InsertStats:
        """Inserts one laser scan: ``ranges`` (B,) [m], beam ``angles`` (B,) [rad] or
        ``angle_min`` + ``angle_increment``, seen from ``pose`` (``world_from_robot``) with the
        laser at ``mount`` (``robot_from_laser``). REP 117: ranges in [range_min_m,
        range_max_m) mark their cell; ``+inf`` or >= ``range_max_m`` clear up to range_max_m
        without marking; ``-inf`` or below range_min_m are ignored; NaN raises GeometryError."""
        r, a, amin, ainc = laser_args(ranges, angles, angle_min, angle_increment)
        out = self._native.insert_laser(
            r,
            a,
            amin,
            ainc,
            float(range_min_m),
            float(range_max_m),
            as_pose(pose, "pose"),
            as_pose(mount, "mount"),
        )
        return InsertStats(*out)

    def insert_lasers(
        self,
        ranges,
        *,
        poses,
        range_max_m: float,
        range_min_m: float = 0.0,
        angles=None,
        angle_min: Optional[float] = None,
        angle_increment: Optional[float] = None,
        mount=(0.0, 0.0, 0.0),
    ) -> InsertStats:
        """Many laser scans at once (the fast path): ``ranges`` (N, B) [m], ``poses`` (N, 3)
        ``world_from_robot`` rows; other arguments as :meth:`insert_laser`. Everything is
        checked before the first scan goes in (a bad scan leaves the map unchanged); the GIL
        is released while inserting."""
        r, a, amin, ainc = laser_args(ranges, angles, angle_min, angle_increment, two_d=True)
        p = as_poses(poses, "poses")
        if p.shape[0] != r.shape[0]:
            raise LengthMismatchError(f"{r.shape[0]} scans but {p.shape[0]} poses")
        out = self._native.insert_lasers(
            r, p, a, amin, ainc, float(range_min_m), float(range_max_m), as_pose(mount, "mount")
        )
        return InsertStats(*out)

    def insert_sonar(
        self, ranges, *, pose, beam_width_rad: float, range_max_m: float, mounts=(0.0, 0.0, 0.0)
    ) -> InsertStats:
        """Sonar readings fired together at ``pose``: ``ranges`` [m] (a number or (K,)), one
        mount (``robot_from_sonar``) per reading as (K, 3). The arc at each range gets
        occupied evidence, the cone inside it free; ``+inf`` or >= range_max_m clears the cone
        up to range_max_m."""
        r, m = sonar_args(ranges, mounts)
        return InsertStats(
            *self._native.insert_sonar(
                r, m, float(beam_width_rad), float(range_max_m), as_pose(pose, "pose")
            )
        )

    def insert_rays(
        self, starts, ends, *, hits=True, evidence: Optional[EvidenceLike] = None
    ) -> InsertStats:
        """Any other range sensor: one batch of world rays, ``starts`` and ``ends`` (N, 2) [m];
        ``hits`` (bool or (N,)) says whether each end is an obstacle. Free space runs from
        start to end, with ``evidence`` (default: the grid's ``visual`` evidence). GIL
        released."""
        s = np.ascontiguousarray(starts, dtype=np.float64).reshape(-1, 2)
        e = np.ascontiguousarray(ends, dtype=np.float64).reshape(-1, 2)
        h = np.ascontiguousarray(np.broadcast_to(np.asarray(hits, dtype=bool), (s.shape[0],)))
        if evidence is None:
            evidence = tuple(self._native.inserter_options["visual"].values())
        ev = as_evidence(evidence, "evidence")
        return InsertStats(
            *self._native.insert_rays(s, e, h, float(ev.hit_nats), float(ev.miss_nats))
        )

    def evidence(self, *, name: str = ""):
        """The unclamped evidence layer as an :class:`~floorscan.mapping.evidence.EvidenceMap` (the grid
        must have been made with ``keep_evidence=True``)."""
        return EvidenceMap.from_grid(self, name=name)

    def write_raw(self, values: np.ndarray, *, x_cell: int, y_cell: int) -> None:
        """Writes an (H, W) int16 array of log-odds [1/1000 nat] with its first cell at
        (x_cell, y_cell) (values are clamped to the map's bounds)."""
        try:
            v = np.ascontiguousarray(values, dtype=np.int16)
        except (TypeError, ValueError, OverflowError) as e:
            raise LengthMismatchError(f"values must be an (H, W) int16 array: {e}") from None
        if v.ndim != 2:
            raise LengthMismatchError(f"values must be (H, W), got shape {v.shape}")
        x, y = cell_index("x_cell", x_cell), cell_index("y_cell", y_cell)
        self._native.write_values(x, y, v)

    def save(self, path: PathLike, *, mode: str = "trinary", extent=None):
        """Writes a ROS map_server map: ``path`` (.yaml) and an 8-bit PGM beside it, atomically.
        See :func:`floorscan.formats.map_server.save_map`."""
        return save_map(self, path, mode=mode, extent=extent)

    @classmethod
    def load(cls, path: PathLike, *, grow: bool = False, **options) -> OccupancyGrid:
        """Reads a ROS map_server map (YAML + PGM/PNG) into a grid whose lattice is the image's:
        cell (0, 0) is the bottom-left pixel, at the YAML's origin. The grid has the image's
        fixed bounds, or grows (``grow=True``) if more data is to be added around it.
        ``options`` are the grid's other options (``cell_size_m``, ``origin_m`` and
        ``bounds_m`` come from the file). Pixels are read as map_server reads them
        (:func:`floorscan.formats.map_server.pixels_to_units`)."""
        for key in ("cell_size_m", "origin_m", "bounds_m"):
            if key in options:
                raise OptionError(f"`{key}` comes from the map file; do not pass it")
        meta = read_map_yaml(path)
        grey, alpha = read_map_image(meta["image"])
        res, (ox, oy) = meta["resolution"], meta["origin"]
        h, w = grey.shape
        bounds = None
        if not grow:
            # A quarter cell inside the image's edges: exactly its cells, whatever the rounding.
            bounds = (
                (ox + 0.25 * res, oy + 0.25 * res),
                (ox + (w - 0.25) * res, oy + (h - 0.25) * res),
            )
        grid = cls(cell_size_m=res, origin_m=(ox, oy), bounds_m=bounds, **options)
        lo, hi, _, _ = grid._native.limits()
        values = pixels_to_units(grey, alpha, meta, lo, hi)
        grid.write_raw(np.ascontiguousarray(values[::-1]), x_cell=0, y_cell=0)
        return grid

    @classmethod
    def from_evidence(cls, evidence: EvidenceMap) -> OccupancyGrid:
        """A growing grid on the evidence map's lattice holding its clamped log-odds
        (:meth:`~floorscan.mapping.evidence.EvidenceMap.clamped`)."""
        grid = cls(cell_size_m=evidence.cell_size_m, origin_m=evidence.origin_m, **evidence.options)
        if evidence.values.size:
            grid.write_raw(evidence.clamped(), x_cell=0, y_cell=0)
        return grid

    def __repr__(self) -> str:
        e = self.extent
        fixed = self._native.fixed_cells
        kind = "fixed bounds" if fixed else "growing"
        return (
            f"OccupancyGrid({kind}, {self.cell_size_m} m cells, "
            f"extent {e.width} x {e.height} cells at {e.origin_m})"
        )
