"""The simulator's solids as the robot's body meets them (truth, never shown to the robot's
planner): the footprint polygons of every solid whose base is below the robot's height, exact
distances from a point to them, and an ideal 2-D laser cast against them."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Tuple

import numpy as np


@dataclass(frozen=True)
class Solids:
    """Edges of the solids' footprints: ``a``, ``b`` (E, 2) segment ends [m, world frame];
    ``polygons``: the footprints, for inside tests."""

    a: np.ndarray
    b: np.ndarray
    polygons: Tuple[np.ndarray, ...]
    owner: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    """Per edge, the index of its polygon (E,)."""

    @classmethod
    def of_world(cls, world, *, robot_height_m: float = 0.5) -> Solids:
        """The solids of a :class:`floorscan.sim.World` that a robot ``robot_height_m`` [m]
        tall can hit: those whose base is below its top (a table top above it is not one)."""
        data = json.loads(world._native.to_json())
        polys = []
        for s in data["solids"]:
            if s["base_m"] >= robot_height_m:
                continue
            polys.append(np.array([[p["x"], p["y"]] for p in s["polygon"]], dtype=np.float64))
        return cls.of_polygons(polys)

    @classmethod
    def of_polygons(cls, polygons) -> Solids:
        polys = tuple(np.asarray(p, dtype=np.float64).reshape(-1, 2) for p in polygons)
        if not polys:
            empty = np.zeros((0, 2))
            return cls(empty, empty, ())
        a = np.concatenate(polys)
        b = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
        owner = np.repeat(np.arange(len(polys)), [len(p) for p in polys])
        return cls(a, b, polys, owner)

    def inside(self, x: float, y: float) -> bool:
        """True when (x, y) [m] lies inside a solid's footprint."""
        if len(self.a) == 0:
            return False
        # even-odd rule over every edge at once, the crossings counted per polygon
        ya, yb = self.a[:, 1], self.b[:, 1]
        cross = (ya > y) != (yb > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xint = (self.b[:, 0] - self.a[:, 0]) * (y - ya) / (yb - ya) + self.a[:, 0]
        hits = np.bincount(self.owner[cross & (x < xint)], minlength=len(self.polygons))
        return bool((hits % 2).any())

    def clearance(self, x: float, y: float) -> float:
        """Distance [m] from (x, y) to the nearest solid's footprint (0 inside one; +inf
        without solids)."""
        if len(self.a) == 0:
            return float("inf")
        if self.inside(x, y):
            return 0.0
        q = self.nearest(x, y)
        return float(math.hypot(q[0] - x, q[1] - y))

    def nearest(self, x: float, y: float) -> Tuple[float, float]:
        """The point [m] of the solids' footprint edges nearest to (x, y) (what a bumper
        touches first; (nan, nan) without solids)."""
        if len(self.a) == 0:
            return (math.nan, math.nan)
        p = np.array([x, y])
        d = self.b - self.a
        t = np.clip(np.einsum("ij,ij->i", p - self.a, d) / np.maximum((d * d).sum(1), 1e-18), 0, 1)
        q = self.a + t[:, None] * d
        i = int(((q - p) ** 2).sum(1).argmin())
        return (float(q[i, 0]), float(q[i, 1]))

    def laser(
        self, pose, angles: np.ndarray, *, range_max_m: float, height_offset: float = 0.0
    ) -> np.ndarray:
        """Ideal 2-D laser ranges [m] from ``pose`` (x, y, yaw) at ``angles`` [rad, robot
        frame]: the nearest footprint edge along each ray, +inf beyond ``range_max_m``
        (REP 117)."""
        x, y, yaw = (float(v) for v in pose)
        ang = np.asarray(angles, dtype=np.float64) + yaw
        dx, dy = np.cos(ang)[:, None], np.sin(ang)[:, None]
        ex = (self.b - self.a)[None, :, 0]
        ey = (self.b - self.a)[None, :, 1]
        wx = self.a[None, :, 0] - x
        wy = self.a[None, :, 1] - y
        den = dx * ey - dy * ex
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (wx * ey - wy * ex) / den
            s = (wx * dy - wy * dx) / den
        ok = (np.abs(den) > 1e-12) & (t > 0) & (s >= 0) & (s <= 1)
        t = np.where(ok, t, np.inf)
        r = t.min(axis=1) if t.shape[1] else np.full(len(ang), np.inf)
        r[r > range_max_m] = np.inf
        return r
