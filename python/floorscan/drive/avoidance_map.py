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

The updates run in the Rust core (``floorscan_core::avoidance_map``, in place on the numpy
layers kept here); tests/avoidance_map_reference.py keeps the numpy/OpenCV implementation they
replaced, which they equal cell for cell.
"""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np

from .._native.drive import AvoidanceMap as _NativeAvoidanceMap
from .._native.drive import decay as _decay
from ..formats.trajectory import compose as _compose
from ..mapping.grid_views import GridExtent
from ..options import OptionsObject
from ..ranging.scan import ColumnStatus
from .sensor_model import VisualSensorModel

_NO_EVIDENCE = 0.05  # |log odds| below this: no evidence (unknown), whatever the calibration


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


def _logit(p: float) -> float:
    return math.log(p / (1.0 - p))


_DEFAULT_MODEL = VisualSensorModel()
_LAYERS = (
    "log_odds",
    "bumps",
    "confirmed",
    "plan_log_odds",
    "plan_confirmed",
    "plan_near_hits",
)
"""The map's layers, scrolled together by :meth:`AvoidanceMap.recenter`."""
_BOUNDARY = int(ColumnStatus.BOUNDARY)  # a plain int compares faster than the enum


class AvoidanceMap:
    """A scrolling log-odds window (odometry frame, REP 103; row 0 = lowest y)."""

    def __init__(self, options: Optional[AvoidanceMapOptions] = None, *, center=(0, 0)):
        options = AvoidanceMapOptions() if options is None else options
        self.options = options
        self.cell = options.cell_size_m
        self.n = int(round(options.size_m / self.cell))
        self.log_odds = np.zeros((self.n, self.n), np.float32)
        self.bumps = np.zeros((self.n, self.n), np.float32)
        # 1 where a hit from VisualSensorModel.confirm_range_m or farther confirmed the cell
        self.confirmed = np.zeros((self.n, self.n), np.uint8)
        # the planner's layers: the same evidence, but a confirmed obstacle that the floor
        # seen beyond it contradicts clears by VisualSensorModel.confirmed_clearing of it a
        # frame (log_odds clear in full, so probabilities() keeps its calibration)
        self.plan_log_odds = np.zeros((self.n, self.n), np.float32)
        self.plan_confirmed = np.zeros((self.n, self.n), np.uint8)
        # 1 where the last visual insertion hit from nearer than
        # VisualSensorModel.persist_range_m: such a hit enters the planner's layers when the
        # next one hits there again (or the planner has evidence the place is occupied)
        self.plan_near_hits = np.zeros((self.n, self.n), np.uint8)
        self.x_cell = 0
        self.y_cell = 0
        self.recenter(*center[:2])
        self._native = _NativeAvoidanceMap(self.n, self.cell, tuple(options.clamp_nats))
        self._plan_occ = _logit(options.occupied_threshold)
        self._plan_free = _logit(options.free_threshold)

    # --- geometry -------------------------------------------------------------------------
    @property
    def origin_m(self) -> Tuple[float, float]:
        return (self.x_cell * self.cell, self.y_cell * self.cell)

    @property
    def extent(self) -> GridExtent:
        return GridExtent(self.x_cell, self.y_cell, self.n, self.n, self.cell, self.origin_m)

    def recenter(self, x: float, y: float) -> None:
        """Scrolls by whole cells so (x, y) [m] lies within a quarter window of the centre;
        cells that enter are unknown."""
        half = self.n // 2
        cx, cy = int(math.floor(x / self.cell)) - half, int(math.floor(y / self.cell)) - half
        if abs(cx - self.x_cell) <= self.n // 4 and abs(cy - self.y_cell) <= self.n // 4:
            return
        dx, dy = cx - self.x_cell, cy - self.y_cell
        n = self.n
        for name in _LAYERS:
            layer = getattr(self, name)
            out = np.zeros_like(layer)
            if abs(dx) < n and abs(dy) < n:
                src = layer[max(dy, 0) : n + min(dy, 0), max(dx, 0) : n + min(dx, 0)]
                out[max(-dy, 0) : n + min(-dy, 0), max(-dx, 0) : n + min(-dx, 0)] = src
            setattr(self, name, out)
        self.x_cell, self.y_cell = cx, cy

    def to_cells(self, x, y):
        """World (odometry frame) points [m] to fractional cell coordinates (col, row)."""
        return (np.asarray(x) / self.cell - self.x_cell, np.asarray(y) / self.cell - self.y_cell)

    # --- views ----------------------------------------------------------------------------
    def probabilities(self) -> np.ndarray:
        """Calibrated occupancy probabilities (``probability_knots``, or the Platt curve of
        ``probability_scale`` / ``probability_offset``); cells without evidence read 0.5."""
        a, b = self.options.probability_scale, self.options.probability_offset
        L = self.log_odds.astype(np.float64)
        knots = self.options.probability_knots
        if knots is not None:
            k = np.asarray(knots, np.float64)
            p = np.interp(L, k[:, 0], k[:, 1])
        else:
            p = 1.0 / (1.0 + np.exp(-(a * L + b)))
        p[np.abs(self.log_odds) < _NO_EVIDENCE] = 0.5
        return p

    def occupancy_classes(self) -> np.ndarray:
        """(H, W) uint8: 0 free, 1 unknown, 2 occupied: the planner's decisions, from the raw
        evidence of the planner's layer against logit(free_threshold) /
        logit(occupied_threshold) (the calibrated probabilities of :meth:`probabilities` say
        how often such a decision is right; a single calibrated reading never reaches 0.65,
        and the map must still show it)."""
        c = np.ones(self.plan_log_odds.shape, np.uint8)
        c[self.known() & (self.plan_log_odds < self._plan_free)] = 0
        c[self.occupied()] = 2
        return c

    def known(self) -> np.ndarray:
        """Cells the planner has evidence for (either way)."""
        return np.abs(self.plan_log_odds) >= _NO_EVIDENCE

    def occupied(self) -> np.ndarray:
        """The planner's obstacles: raw evidence of the planner's layer above
        logit(occupied_threshold), before the output calibration (one confident reading
        suffices: for avoidance a missed obstacle costs more than a detour), or the bumper's
        marks."""
        return (self.plan_log_odds > self._plan_occ) | (self.bumps > 0.5)

    # --- updates --------------------------------------------------------------------------
    def decay(self, dt_s: float) -> None:
        """Forgets: the evidence shrinks by 2^(-dt / half_life_s), the bumper's marks by
        2^(-dt / bump_half_life_s)."""
        if dt_s <= 0:
            return
        hl, bump_hl = self.options.half_life_s, self.options.bump_half_life_s
        if hl is not None:
            _decay(self.log_odds, np.float32(0.5 ** (dt_s / hl)))
            _decay(self.plan_log_odds, np.float32(0.5 ** (dt_s / hl)))
        if bump_hl is not None:
            _decay(self.bumps, np.float32(0.5 ** (dt_s / bump_hl)))

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
        f64 = np.float64
        self._native.insert_visual(
            self.log_odds,
            self.confirmed,
            self.plan_log_odds,
            self.plan_confirmed,
            self.plan_near_hits,
            (self.x_cell, self.y_cell),
            cam,
            status,
            np.ascontiguousarray(scan.x, f64),
            np.ascontiguousarray(scan.y, f64),
            np.ascontiguousarray(scan.near_x, f64),
            np.ascontiguousarray(scan.near_y, f64),
            np.ascontiguousarray(scan.footprints, f64),
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
        half_length_m = self.options.bump_face_half_length_m
        a = pose[2] + bearing_rad
        t = np.linspace(-half_length_m, half_length_m, int(4 * half_length_m / self.cell) + 2)
        px = pose[0] + distance_m * math.cos(a) - t * math.sin(a)
        py = pose[1] + distance_m * math.sin(a) + t * math.cos(a)
        cx, cy = self.to_cells(px, py)
        ok = (cx >= 0) & (cx < self.n) & (cy >= 0) & (cy < self.n)
        self.bumps[cy[ok].astype(int), cx[ok].astype(int)] = 1.0

    def insert_laser(
        self,
        ranges: np.ndarray,
        angles: np.ndarray,
        pose,
        *,
        range_max_m: float,
        hit_nats: float = 2.2,
        miss_nats: float = -2.0,
    ) -> None:
        """An ideal 2-D laser scan (REP 117 ranges [m] at ``angles`` [rad, robot frame]) from
        ``pose``: free up to each return (or ``range_max_m``), occupied at the return.
        Evidence defaults: p = 0.9 / 0.12, an ideal sensor's strong constant evidence."""
        r = np.asarray(ranges, np.float64)
        a = np.asarray(angles, np.float64) + pose[2]
        end = np.where(np.isfinite(r), r, range_max_m)
        ecx, ecy = self.to_cells(pose[0] + end * np.cos(a), pose[1] + end * np.sin(a))
        pc = self.to_cells(pose[0], pose[1])
        self._native.insert_laser(
            self.log_odds,
            self.plan_log_odds,
            (float(pc[0]), float(pc[1])),
            np.ascontiguousarray(np.stack([ecx, ecy], 1), np.float64),
            np.isfinite(r),
            hit_nats,
            miss_nats,
        )
