"""The local map (paper IV.A): a square window fixed to the robot, fed with pose changes only.

Its frame ("local") is the frame the odometry increments are integrated in: the window is
aligned with it and scrolls by whole cells as the robot moves, keeping the robot's sub-cell
position exactly, so nothing drifts. :meth:`LocalMap.robot_view` resamples it in the robot's
own frame.
"""

from __future__ import annotations

from typing import Any, Dict, Optional

import numpy as np

from .._native import mapping as _native
from ..errors import ArgumentTypeError, OptionError
from ..options import plain
from ..ranging.scan import Scan
from .grid import InsertStats, laser_args, sonar_args
from .grid_options import as_pose, split_options
from .grid_views import GridViews
from .log_odds import UNITS_PER_NAT, probabilities_from_units


class LocalMap(GridViews):
    """A robot-centred occupancy window.

    Parameters (all keyword-only):
        size_m: side of the square window [m] (the core's ``LocalMapOptions``; unset: its
            default, the paper's 384 x 384 cm).
        pose: the robot's starting pose in the local frame ``(x, y, yaw)``; default the
            origin (a fresh odometry frame).
        **options: the grid and inserter options, as :class:`~floorscan.OccupancyGrid`'s
            (``bounds_m`` excepted: the window is the bound). ``visual`` is the local map's own
            (``LocalMapOptions.visual``, ``[local_map.visual]``): its default settles a view
            within two frames (hit +0.85, miss -0.75 nats) where the global map's (-0.4)
            needs four; ``floorscan config --default`` prints both.

    Arrays, images and queries (:meth:`raw`, :meth:`probabilities`, :meth:`is_free`,
    :meth:`distance_to_nearest_occupied`, ...) are in the local frame over the window.

    >>> import floorscan
    >>> local = floorscan.LocalMap()
    >>> local.extent.shape
    (96, 96)
    >>> local.move_by((0.5, 0.0, 0.0))
    >>> local.pose
    (0.5, 0.0, 0.0)
    """

    def __init__(
        self, *, size_m: Optional[float] = None, pose=(0.0, 0.0, 0.0), **options: Any
    ) -> None:
        go, io = split_options(options)
        local: Dict[str, Any] = {"grid": go}
        if "visual" in io:  # the local map's own visual evidence (LocalMapOptions.visual)
            local["visual"] = io.pop("visual")
        if size_m is not None:
            local["size_m"] = plain(size_m)
        self._native = _native.LocalMap(local, io, as_pose(pose, "pose"))

    @property
    def options(self) -> Dict[str, Any]:
        """The validated options, every field (the core's ``LocalMapOptions`` serde form)."""
        return self._native.options

    @property
    def pose(self):
        """The robot's pose in the local frame ``(x [m], y [m], yaw [rad])``."""
        return self._native.pose

    def move_by(self, delta) -> None:
        """Moves the robot by an odometry increment ``robot_before_from_robot_after``
        ``(dx, dy, dyaw)`` (in the robot's frame before the move) and scrolls the window."""
        self._native.move_by(as_pose(delta, "delta"))

    def move_to(self, pose) -> None:
        """Places the robot at ``pose`` in the local frame (e.g. the odometry pose) and
        scrolls the window."""
        self._native.move_to(as_pose(pose, "pose"))

    def _place(self, pose) -> None:
        if pose is not None:
            self.move_to(pose)

    def insert_scan(self, scan: Scan, pose=None, mount=(0.0, 0.0, 0.0)) -> InsertStats:
        """A visual scan seen from ``pose`` (the robot in the local frame, e.g. the odometry
        pose; the map moves there first) or, with ``pose=None``, from the current pose; the
        camera at ``mount`` (``robot_from_camera``). Same argument order as
        :meth:`floorscan.OccupancyGrid.insert_scan`."""
        if not isinstance(scan, Scan):
            raise ArgumentTypeError(f"scan must be a floorscan.Scan, got {type(scan).__name__}")
        self._place(pose)
        return InsertStats(*self._native.insert_scan(scan._native, as_pose(mount, "mount")))

    def insert_laser(
        self,
        ranges,
        *,
        range_max_m: float,
        range_min_m: float = 0.0,
        angles=None,
        angle_min: Optional[float] = None,
        angle_increment: Optional[float] = None,
        mount=(0.0, 0.0, 0.0),
        pose=None,
    ) -> InsertStats:
        """A laser scan seen from ``pose`` (local frame; default the current pose), rules as
        :meth:`floorscan.OccupancyGrid.insert_laser`."""
        r, a, amin, ainc = laser_args(ranges, angles, angle_min, angle_increment)
        self._place(pose)
        return InsertStats(
            *self._native.insert_laser(
                r, a, amin, ainc, float(range_min_m), float(range_max_m), as_pose(mount, "mount")
            )
        )

    def insert_sonar(
        self,
        ranges,
        *,
        beam_width_rad: float,
        range_max_m: float,
        mounts=(0.0, 0.0, 0.0),
        pose=None,
    ) -> InsertStats:
        """Sonar readings taken at ``pose`` (local frame; default the current pose), rules as
        :meth:`floorscan.OccupancyGrid.insert_sonar`."""
        r, m = sonar_args(ranges, mounts)
        self._place(pose)
        return InsertStats(
            *self._native.insert_sonar(r, m, float(beam_width_rad), float(range_max_m))
        )

    def robot_view(
        self,
        *,
        width: Optional[int] = None,
        height: Optional[int] = None,
        kind: str = "probability",
    ) -> np.ndarray:
        """The window resampled in the robot's frame (x forward, y left), centred on the
        robot, cells of the map's size: (height, width) array, row 0 at the robot's right
        (most negative y), column 0 behind it (most negative x); default the window's size.
        ``kind``: ``"probability"`` (float64), ``"log_odds"`` (float32 nats) or ``"raw"``
        (int16). Outside the window reads as unknown."""
        w = self.extent.width if width is None else int(width)
        h = self.extent.height if height is None else int(height)
        if w < 1 or h < 1 or w > 8192 or h > 8192:
            raise OptionError(
                f"invalid option `width`/`height`: must be in 1..=8192, got {w} x {h}"
            )
        raw = self._native.robot_view(w, h)
        if kind == "raw":
            return raw
        if kind == "log_odds":
            return (raw.astype(np.float32) / np.float32(UNITS_PER_NAT)).astype(np.float32)
        if kind == "probability":
            return probabilities_from_units(raw)
        raise OptionError(
            f"invalid option `kind`: expected probability, log_odds or raw, got {kind!r}"
        )

    def __repr__(self) -> str:
        e = self.extent
        return (
            f"LocalMap({e.width} x {e.height} cells of {self.cell_size_m} m, robot at {self.pose})"
        )
