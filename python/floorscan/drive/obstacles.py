"""Obstacles placed on a world's route, for the drive suite: boxes, bins, chairs and small
tables (four legs under an overhanging top) at the middle of the tour's longer legs, shifted
sideways as little as needed to leave a way past for the robot (checked on the true
occupancy: a 0.35 m clearance, the robot's radius plus its planner's padding and 10 cm)."""

from __future__ import annotations

import math
from typing import List, Optional, Tuple

import numpy as np

KINDS = ("box", "chair", "table", "bin")


def _snippet(kind: str, x: float, y: float, yaw: float) -> str:
    if kind == "box":
        return (
            f"\n[[boxes]]\ncenter = [{x:.3f}, {y:.3f}]\nsize = [0.40, 0.40]\n"
            f'yaw = {yaw:.3f}\nheight_m = 0.50\nappearance = "wood"\n'
        )
    if kind == "bin":
        return (
            f"\n[[boxes]]\ncenter = [{x:.3f}, {y:.3f}]\nradius = 0.15\n"
            'height_m = 0.35\nappearance = "metal"\n'
        )
    if kind == "chair":
        return f"\n[[chairs]]\ncenter = [{x:.3f}, {y:.3f}]\nyaw = {yaw:.3f}\n"
    return (
        f"\n[[tables]]\ncenter = [{x:.3f}, {y:.3f}]\nsize = [0.6, 0.6]\n"
        f"yaw = {yaw:.3f}\nheight_m = 0.72\n"
    )


def _passable(world, a, b, clearance_m: float) -> bool:
    """True when a circle of radius ``clearance_m`` can travel from a to b (true map)."""
    import cv2

    res = 0.05
    r = world.occupancy(resolution_m=res)
    free = (r.cells == 0).astype(np.uint8) * 255
    d = cv2.distanceTransform(free, cv2.DIST_L2, 5) * res
    ok = (d > clearance_m).astype(np.uint8)
    _, labels = cv2.connectedComponents(ok, connectivity=8)

    def label(p):
        i = int((p[0] - r.origin[0]) / res)
        j = int((p[1] - r.origin[1]) / res)
        if not (0 <= j < labels.shape[0] and 0 <= i < labels.shape[1]):
            return 0
        # the nearest labelled cell within 0.3 m (waypoints may sit near a wall)
        win = labels[max(j - 6, 0) : j + 7, max(i - 6, 0) : i + 7]
        vals = win[win > 0]
        return int(np.bincount(vals).argmax()) if vals.size else 0

    la, lb = label(a), label(b)
    return la > 0 and la == lb


def with_obstacles(
    world,
    *,
    count: int = 3,
    min_leg_m: float = 2.0,
    clearance_m: float = 0.35,
    kinds=KINDS,
) -> Tuple[object, List[dict]]:
    """A copy of ``world`` (a :class:`floorscan.sim.World` read from TOML) with up to
    ``count`` obstacles on the tour's legs longer than ``min_leg_m`` [m], and their list."""
    from ..sim import World

    text = world.source
    if text is None:
        raise ValueError("the world has no TOML source to add obstacles to")
    tour = np.vstack([np.asarray(world.start[:2])[None, :], world.tour])
    legs = [(tour[i], tour[i + 1]) for i in range(len(tour) - 1)]
    legs = [leg for leg in legs if math.dist(*leg) >= min_leg_m]
    placed: List[dict] = []
    current = world
    for n, (a, b) in enumerate(legs):
        if len(placed) >= count:
            break
        kind = kinds[len(placed) % len(kinds)]
        u = (b - a) / math.dist(a, b)
        side = np.array([-u[1], u[0]])
        mid = a + (b - a) * 0.5
        yaw = math.atan2(u[1], u[0])
        if any(math.dist(mid, (q["x"], q["y"])) < 1.5 for q in placed):
            continue
        chosen: Optional[object] = None
        for off in (0.0, 0.25, -0.25, 0.45, -0.45):
            p = mid + off * side
            cand_text = text + _snippet(kind, p[0], p[1], yaw)
            cand = World.from_toml(cand_text, source_name=f"{world.name}+obstacles")
            if _passable(cand, a, b, clearance_m):
                chosen, text = cand, cand_text
                placed.append(
                    {
                        "kind": kind,
                        "x": round(float(p[0]), 3),
                        "y": round(float(p[1]), 3),
                        "offset_m": off,
                        "leg": n,
                    }
                )
                break
        if chosen is not None:
            current = chosen
    return current, placed
