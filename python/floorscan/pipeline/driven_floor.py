"""The appearance ranger's refresh from floor the robot has driven over (issue 13).

The appearance ranger learns the floor from a band just in front of the robot. Floor that
never enters that band while the model remembers it (a rug, a doorway's linoleum, a sunlit
patch) reads as an obstacle every time it is seen from afar. The robot knows better once it
has driven over it: a boundary whose ground point the robot's origin later passes within
``driven_floor_radius_m`` was floor, and the pixels that made it (the run of rows that stopped
the column's scan) are learned as floor (:meth:`AppearanceRanger.learn_driven_floor`), each
only if the frame taken there confirms it: its reference band, the floor just in front of the
robot at that place, must look like it. A boundary the robot only seemed to reach (odometry
drift carrying the estimate onto a wall's base, a chair leg passed closely) shows the real
floor in that band, not the boundary's pixels, and teaches nothing. Without that check, a
corridor with drifting odometry went from 1.0 to 8.1 % wrong columns and the furnished room
from 10.7 to 12.8 % (EVALUATION.md, "Refresh from floor driven over").

:class:`DrivenFloor` remembers each frame's boundaries in world coordinates with their pixels,
for at most ``MAX_AGE_S`` and ``MAX_PENDING`` boundaries in a ring (bounded memory and work: a
boundary reached later than that was seen long ago and odometry has drifted since; frames are
remembered at most every ``MIN_INTERVAL_S``, as one boundary is seen in many frames), and hands
those the robot drives through to the ranger. ``floorscan run`` / ``floorscan eval`` (the
:class:`~floorscan.pipeline.mapper.Mapper`) and ``floorscan drive`` use it with their
odometry poses whenever the ranger is ``appearance`` or ``fused``.
"""

from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np

from ..formats.trajectory import compose
from ..ranging.appearance import AppearanceRanger
from ..ranging.scan import ColumnStatus

MAX_PENDING = 20_000
"""Most boundaries remembered (a ring: the oldest are overwritten): 20 000 x 40 bytes."""
MAX_AGE_S = 30.0
"""Boundaries older than this [s] are forgotten: at 0.3 m/s a boundary seen 3 m ahead is
reached in 10 s; after 30 s odometry's drift could put the robot over a real obstacle's
base."""
MIN_INTERVAL_S = 0.2
"""Frames closer than this [s] to the last remembered one are not remembered (30 s of 104
columns at 5 frames/s fit the ring)."""


def appearance_part(ranger) -> Optional[AppearanceRanger]:
    """The appearance ranger of ``ranger`` (itself, or a fused ranger's), None for the edge
    ranger."""
    part = getattr(ranger, "appearance", ranger)
    return part if isinstance(part, AppearanceRanger) else None


def driven_floor_for(ranger) -> Optional[DrivenFloor]:
    """The refresh for ``ranger``, None when it has no appearance part or its
    ``driven_floor_radius_m`` is 0 (off)."""
    part = appearance_part(ranger)
    if part is None:
        return None
    radius = float(part.options["driven_floor_radius_m"])
    return DrivenFloor(part, radius) if radius > 0 else None


class DrivenFloor:
    """Boundaries remembered until the robot drives through them (see the module)."""

    def __init__(self, ranger: AppearanceRanger, radius_m: float) -> None:
        self.ranger = ranger
        self.radius_m = float(radius_m)
        self._x = np.zeros(MAX_PENDING)
        self._y = np.zeros(MAX_PENDING)
        self._t = np.full(MAX_PENDING, -np.inf)  # -inf: empty or consumed
        # per boundary, its pixels as the ranger packs them (BOUNDARY_SAMPLES of them)
        width = ranger.boundary_samples().shape[1]
        self._samples = np.zeros((MAX_PENDING, width), np.uint32)
        self._next = 0
        self._last_kept = -np.inf
        self.boundaries_driven = 0
        """Boundaries the robot has driven through (their pixels were learned)."""
        self.samples_learned = 0

    def pending(self, timestamp: float) -> int:
        """Boundaries remembered at ``timestamp`` [s], not yet driven through."""
        return int(np.count_nonzero(self._t >= float(timestamp) - MAX_AGE_S))

    def update(self, pose: Sequence[float], mount: Sequence[float], timestamp: float) -> int:
        """Call after each scan of the ranger with the frame's ``pose`` (world_from_robot)
        and ``mount`` (robot_from_camera): hands the remembered boundaries the robot has now
        reached (see the module) to the ranger, which learns the pixels this frame confirms,
        then remembers this frame's boundaries. Returns the boundaries reached now."""
        x, y, t = float(pose[0]), float(pose[1]), float(timestamp)
        # a strip test on x first: one pass over the ring, the rest on the few in the strip
        near = np.flatnonzero(np.abs(self._x - x) <= self.radius_m)
        if near.size:
            d2 = (self._x[near] - x) ** 2 + (self._y[near] - y) ** 2
            near = near[(d2 <= self.radius_m**2) & (self._t[near] >= t - MAX_AGE_S)]
        driven = int(near.size)
        if driven:
            self.samples_learned += self.ranger.learn_driven_floor(self._samples[near])
            self.boundaries_driven += driven
            self._t[near] = -np.inf
        scan = self.ranger.last_scan
        if scan is None or t - self._last_kept < MIN_INTERVAL_S:
            return driven
        new = scan.status_codes == ColumnStatus.BOUNDARY
        n = min(int(np.count_nonzero(new)), MAX_PENDING)
        if n:
            self._last_kept = t
            cx, cy, cyaw = compose(pose, mount)
            px, py = scan.x[new][:n], scan.y[new][:n]
            c, s = math.cos(cyaw), math.sin(cyaw)
            at = (self._next + np.arange(n)) % MAX_PENDING
            self._x[at] = cx + c * px - s * py
            self._y[at] = cy + s * px + c * py
            self._t[at] = t
            self._samples[at] = self.ranger.boundary_samples()[new][:n]
            self._next = int((self._next + n) % MAX_PENDING)
        return driven
