"""Thin obstacles: how many of the chair and table legs near the robot the range sensor finds
(issue 13: a 3 cm leg at 1 m must not fall between two sampled columns).

A leg is a solid that stands on the floor (base 0) with a footprint no wider than
:data:`LEG_MAX_SIDE_M`. In a frame, a leg is **in view** when it is the true first obstacle of
at least one image column (simulator truth: the column's true boundary lies on the leg's
footprint) at a true range of at most ``within_m``; it is **found** when one of the ranger's
boundary readings lies within :data:`FOUND_TOLERANCE_M` of its footprint. Recall = found /
in view, summed over frames (a leg seen in ten frames counts ten times).

>>> import numpy as np
>>> legs = Legs(centres=np.array([[1.0, 0.0]]), half_sides=np.array([0.0125]))
>>> legs.near(np.array([[1.02, 0.0], [2.0, 0.0]]), margin_m=0.01).tolist()
[[True], [False]]
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..ranging.scan import ColumnStatus, Scan

LEG_MAX_SIDE_M = 0.08
"""Widest footprint [m] counted as a leg (chair legs are 2.5 cm, table legs 5 cm)."""
FOUND_TOLERANCE_M = 0.05
"""Farthest a boundary reading may lie from a leg's footprint [m] and still find it (the
ranger's own error at 1 m is a few cm)."""
ON_LEG_M = 0.005
"""Slack [m] for a true boundary point to count as lying on a leg's footprint."""
BOUNDARY = ColumnStatus.BOUNDARY


@dataclass(frozen=True)
class Legs:
    """Leg footprints: ``centres`` (L, 2) [m, world frame] and ``half_sides`` (L,) [m] (half
    the footprint's widest side)."""

    centres: np.ndarray
    half_sides: np.ndarray

    @classmethod
    def of_world(cls, world) -> Legs:
        """The legs of a :class:`floorscan.sim.World`."""
        centres, halves = [], []
        for solid in json.loads(world._native.to_json())["solids"]:
            poly = np.array([[p["x"], p["y"]] for p in solid["polygon"]], dtype=np.float64)
            side = float((poly.max(axis=0) - poly.min(axis=0)).max())
            if solid["base_m"] <= 0.0 and side <= LEG_MAX_SIDE_M:
                centres.append(poly.mean(axis=0))
                halves.append(side / 2)
        return cls(np.array(centres).reshape(-1, 2), np.array(halves, dtype=np.float64))

    def __len__(self) -> int:
        return len(self.centres)

    def near(self, points: np.ndarray, *, margin_m: float) -> np.ndarray:
        """(P, L) bool: point p within ``margin_m`` of leg l's footprint (taken as a disc of
        its half side)."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        d = np.linalg.norm(p[:, None, :] - self.centres[None, :, :], axis=-1)
        return d <= self.half_sides[None, :] + margin_m


@dataclass(frozen=True)
class LegRecall:
    """Leg sightings in view (``seen``) and found (``found``) over a run's frames."""

    seen: int
    found: int

    @property
    def recall(self) -> float:
        return self.found / self.seen if self.seen else float("nan")


def _to_world(world_from_camera: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    cx, cy, yaw = (float(v) for v in world_from_camera)
    c, s = np.cos(yaw), np.sin(yaw)
    return np.column_stack([cx + c * x - s * y, cy + s * x + c * y])


def leg_recall(legs: Legs, truth, scans: Sequence[Scan], *, within_m: float = 1.0) -> LegRecall:
    """Recall of ``legs`` by ``scans`` (one per frame of a simulated run whose
    :class:`~floorscan.sim.RunTruth` is ``truth``), legs in view within ``within_m`` [m]."""
    seen = found = 0
    if len(legs) == 0:
        return LegRecall(0, 0)
    for k, scan in enumerate(scans):
        status = truth.status[k]
        points = truth.points[k]
        close = (status == BOUNDARY) & (np.hypot(points[:, 0], points[:, 1]) <= within_m)
        if not close.any():
            continue
        in_view = legs.near(truth.obstacle_world[k][close], margin_m=ON_LEG_M).any(axis=0)
        if not in_view.any():
            continue
        hit = scan.status == "boundary"
        readings = _to_world(truth.world_from_camera[k], scan.x[hit], scan.y[hit])
        found_now = legs.near(readings, margin_m=FOUND_TOLERANCE_M).any(axis=0)
        seen += int(in_view.sum())
        found += int((in_view & found_now).sum())
    return LegRecall(seen, found)
