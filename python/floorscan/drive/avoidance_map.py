"""The map the robot avoids obstacles with: a square log-odds window in the odometry frame that
scrolls with the robot, fed visual scans through the calibrated
:class:`~floorscan.drive.VisualSensorModel` (or an ideal laser), and forgetting stale evidence
so obstacles that moved away clear.

The planner reads its own copy of the evidence (``plan_log_odds``, updated in the same
pass), in which a confirmed obstacle that the floor seen beyond it contradicts clears over
several frames (``VisualSensorModel.confirmed_clearing``) and, if asked, a hit near the camera
enters only when the next frame hits there again (``VisualSensorModel.persist_range_m``);
``log_odds``, whose calibrated :meth:`AvoidanceMap.probabilities` must mean what they say,
clear in full and take every hit.

Cells between adjacent columns count as seen: each pair of neighbouring readings fills the
floor quadrilateral between their near edges of view and their ends, so one frame covers the
whole view (a scan of single rays leaves most far cells untouched and needs many frames).

The map, its layers and every update live in the Rust core (``floorscan_core::avoidance_map``);
this class is its Python face (the layers read as numpy copies).
tests/avoidance_map_reference.py keeps the numpy/OpenCV implementation it replaced, which it
equals cell for cell.
"""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from .._native.drive import AvoidanceMap as _NativeAvoidanceMap
from ..formats.trajectory import compose as _compose
from ..mapping.grid_views import GridExtent
from ..options import OptionsObject
from ..ranging.scan import ColumnStatus
from .sensor_model import VisualSensorModel


class AvoidanceMapOptions(OptionsObject, kind="avoidance_map"):
    """The avoidance map's options: the core's ``AvoidanceMapOptions`` (defaults, the reasons
    for each and every rule live there,
    ``crates/floorscan-core/src/navigation/avoidance_map_options.rs``;
    ``floorscan.options.field_docs("avoidance_map")`` reads them): ``size_m``,
    ``cell_size_m``, ``clamp_nats``, ``half_life_s`` and ``bump_half_life_s`` (None: never
    forget), ``bump_face_half_length_m``, ``occupied_threshold`` and ``free_threshold`` (the
    occupancy grid's by default), ``probability_scale`` / ``probability_offset`` (a Platt
    calibration of the fused evidence) or ``probability_knots`` (a monotone calibration,
    used when set). Keyword arguments are any of them (a bad one is an OptionError naming
    it); read-only, ``replace(**changes)`` makes a changed copy.

    >>> AvoidanceMapOptions(size_m=4.0).size_m, AvoidanceMapOptions().clamp_nats
    (4.0, (-2.0, 3.5))
    """

    __slots__ = ()


_DEFAULT_MODEL = VisualSensorModel()
_BOUNDARY = int(ColumnStatus.BOUNDARY)  # a plain int compares faster than the enum
_F64 = np.float64


def _pose(p) -> Tuple[float, float, float]:
    return (float(p[0]), float(p[1]), float(p[2]))


class AvoidanceMap:
    """A scrolling log-odds window (odometry frame, REP 103; row 0 = lowest y) centred near
    ``center`` [m]. Its layers (``log_odds``, ``bumps``, ``confirmed``, ``plan_log_odds``,
    ``plan_confirmed``, ``plan_near_hits``: (n, n) arrays) read as copies and are set whole."""

    def __init__(self, options: Optional[AvoidanceMapOptions] = None, *, center=(0, 0)):
        options = AvoidanceMapOptions() if options is None else options
        self.options = options
        self.cell = options.cell_size_m
        self._native = _NativeAvoidanceMap(options.to_dict(), (float(center[0]), float(center[1])))
        self.n = self._native.side

    # --- geometry -------------------------------------------------------------------------
    @property
    def x_cell(self) -> int:
        """The world cell (column) of the window's first column."""
        return self._native.origin_cells[0]

    @property
    def y_cell(self) -> int:
        """The world cell (row) of the window's first row."""
        return self._native.origin_cells[1]

    @property
    def origin_m(self) -> Tuple[float, float]:
        return (self.x_cell * self.cell, self.y_cell * self.cell)

    @property
    def extent(self) -> GridExtent:
        return GridExtent(self.x_cell, self.y_cell, self.n, self.n, self.cell, self.origin_m)

    def recenter(self, x: float, y: float) -> None:
        """Scrolls by whole cells so (x, y) [m] lies within a quarter window of the centre;
        cells that enter are unknown."""
        self._native.recenter(float(x), float(y))

    def to_cells(self, x, y):
        """World (odometry frame) points [m] to fractional cell coordinates (col, row)."""
        return (np.asarray(x) / self.cell - self.x_cell, np.asarray(y) / self.cell - self.y_cell)

    # --- layers ---------------------------------------------------------------------------
    @property
    def log_odds(self) -> np.ndarray:
        """The map's log odds (n, n) float32 (a copy; set it whole)."""
        return self._native.log_odds

    @log_odds.setter
    def log_odds(self, value) -> None:
        self._native.log_odds = np.ascontiguousarray(value, np.float32)

    @property
    def bumps(self) -> np.ndarray:
        """The bumper's marks (n, n) float32 (a copy)."""
        return self._native.bumps

    @bumps.setter
    def bumps(self, value) -> None:
        self._native.bumps = np.ascontiguousarray(value, np.float32)

    @property
    def confirmed(self) -> np.ndarray:
        """1 where a hit from ``VisualSensorModel.confirm_range_m`` or farther confirmed the
        cell (n, n) uint8 (a copy)."""
        return self._native.confirmed

    @confirmed.setter
    def confirmed(self, value) -> None:
        self._native.confirmed = np.ascontiguousarray(value, np.uint8)

    @property
    def plan_log_odds(self) -> np.ndarray:
        """The planner's log odds (a copy): the same evidence, but a confirmed obstacle that
        the floor seen beyond it contradicts clears by ``confirmed_clearing`` of it a frame."""
        return self._native.plan_log_odds

    @plan_log_odds.setter
    def plan_log_odds(self, value) -> None:
        self._native.plan_log_odds = np.ascontiguousarray(value, np.float32)

    @property
    def plan_confirmed(self) -> np.ndarray:
        """The planner's confirmed obstacles (a copy)."""
        return self._native.plan_confirmed

    @plan_confirmed.setter
    def plan_confirmed(self, value) -> None:
        self._native.plan_confirmed = np.ascontiguousarray(value, np.uint8)

    @property
    def plan_near_hits(self) -> np.ndarray:
        """1 where the last visual insertion hit from nearer than ``persist_range_m``: such a
        hit enters the planner's layers when the next one hits there again (a copy)."""
        return self._native.plan_near_hits

    @plan_near_hits.setter
    def plan_near_hits(self, value) -> None:
        self._native.plan_near_hits = np.ascontiguousarray(value, np.uint8)

    # --- views ----------------------------------------------------------------------------
    def probabilities(self) -> np.ndarray:
        """Calibrated occupancy probabilities (``probability_knots``, or the Platt curve of
        ``probability_scale`` / ``probability_offset``); cells without evidence read 0.5."""
        return self._native.probabilities()

    def occupancy_classes(self) -> np.ndarray:
        """(H, W) uint8: 0 free, 1 unknown, 2 occupied: the planner's decisions, from the raw
        evidence of the planner's layer against logit(free_threshold) /
        logit(occupied_threshold) (the calibrated probabilities of :meth:`probabilities` say
        how often such a decision is right; a single calibrated reading never reaches 0.65,
        and the map must still show it)."""
        return self._native.occupancy_classes()

    def known(self) -> np.ndarray:
        """Cells the planner has evidence for (either way)."""
        return self._native.known()

    def occupied(self) -> np.ndarray:
        """The planner's obstacles: raw evidence of the planner's layer above
        logit(occupied_threshold), before the output calibration (one confident reading
        suffices: for avoidance a missed obstacle costs more than a detour), or the bumper's
        marks."""
        return self._native.occupied()

    # --- updates --------------------------------------------------------------------------
    def decay(self, dt_s: float) -> None:
        """Forgets: the evidence shrinks by 2^(-dt / half_life_s), the bumper's marks by
        2^(-dt / bump_half_life_s)."""
        self._native.decay(float(dt_s))

    def insert_visual(
        self,
        scan,
        pose,
        *,
        mount=(0.0, 0.0, 0.0),
        table=None,
        model: Optional[VisualSensorModel] = None,
    ) -> None:
        """Adds one visual :class:`~floorscan.Scan` seen from ``pose`` (world_from_robot in
        the odometry frame), the camera at ``mount`` (robot_from_camera), with the evidence of
        ``model``; ``table`` (the ranger's :class:`~floorscan.GroundTable`) gives the predicted
        errors."""
        model = _DEFAULT_MODEL if model is None else model
        cam = _compose(pose, mount)
        status = np.asarray(scan.status_codes, np.uint8)
        err = np.full(len(status), np.nan)
        bnd = status == _BOUNDARY
        if table is not None and bnd.any():
            err[bnd] = table.lookup_error(
                np.asarray(scan.columns, np.float64)[bnd], np.asarray(scan.rows)[bnd]
            )
        self._native.insert_visual(
            _pose(cam),
            np.ascontiguousarray(status),
            np.ascontiguousarray(scan.x, _F64),
            np.ascontiguousarray(scan.y, _F64),
            np.ascontiguousarray(scan.near_x, _F64),
            np.ascontiguousarray(scan.near_y, _F64),
            np.ascontiguousarray(scan.footprints, _F64),
            err,
            model,
        )

    def mark_bump(self, pose, bearing_rad: float, distance_m: float) -> None:
        """A bumper contact: the cells on a straight face ``2 bump_face_half_length_m`` long,
        square to ``bearing_rad`` (robot frame) at ``distance_m`` from ``pose``, become
        obstacles in a separate bumper layer, which the camera cannot clear (it may not see
        what the bumper felt) and which forgets with ``bump_half_life_s``. A face, not the
        touched point: what a bumper meets is most often a flat side (a box, a desk, a wall)
        wider than the segment that felt it, and the robot should not bump along it point by
        point."""
        self._native.mark_bump(_pose(pose), float(bearing_rad), float(distance_m))

    def insert_laser(
        self,
        ranges: np.ndarray,
        angles: np.ndarray,
        pose,
        *,
        range_max_m: float,
        hit_nats: Optional[float] = None,
        miss_nats: Optional[float] = None,
    ) -> None:
        """An ideal 2-D laser scan (REP 117 ranges [m] at ``angles`` [rad, robot frame]) from
        ``pose``: free up to each return (or ``range_max_m``), occupied at the return.
        Evidence (None: the core's ideal laser, p = 0.9 / 0.12, strong and constant)."""
        self._native.insert_laser(
            _pose(pose),
            np.ascontiguousarray(ranges, _F64).ravel(),
            np.ascontiguousarray(angles, _F64).ravel(),
            float(range_max_m),
            hit_nats,
            miss_nats,
        )
