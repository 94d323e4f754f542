"""Obstacles placed on a world's route, for the drive suite: boxes, bins, chairs and small
tables (four legs under an overhanging top) at the middle of the tour's longer legs, shifted
sideways as little as needed to leave a way past for the robot no more than 1.5 m
(4-connected) longer than the leg (checked on the true
occupancy: a 0.35 m clearance, the robot's radius plus its planner's padding and 10 cm)."""

from __future__ import annotations

import math
from typing import List, Optional, Tuple

import numpy as np

from ..sim import World

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


def _passable(world, a, b, clearance_m: float, *, detour_m: float = 1.5) -> bool:
    """True when a circle of radius ``clearance_m`` can travel from a to b (true map) within
    ``detour_m`` [m] more than the straight line, inside a box 1.5 m around the leg."""
    from collections import deque

    import cv2

    res = 0.05
    r = world.occupancy(resolution_m=res)
    free = (r.cells == 0).astype(np.uint8) * 255
    d = cv2.distanceTransform(free, cv2.DIST_L2, 5) * res
    ok = d > clearance_m
    h, w = ok.shape

    def cell(p):
        return int((p[0] - r.origin[0]) / res), int((p[1] - r.origin[1]) / res)

    (ia, ja), (ib, jb) = cell(a), cell(b)
    pad = int(1.5 / res)
    i0, i1 = max(min(ia, ib) - pad, 0), min(max(ia, ib) + pad, w - 1)
    j0, j1 = max(min(ja, jb) - pad, 0), min(max(ja, jb) + pad, h - 1)

    def nearest_ok(i, j):
        # waypoints may sit nearer a wall than the clearance: the nearest passable cell
        best = None
        for dj in range(-6, 7):
            for di in range(-6, 7):
                ii, jj = i + di, j + dj
                if i0 <= ii <= i1 and j0 <= jj <= j1 and ok[jj, ii]:
                    if best is None or di * di + dj * dj < best[0]:
                        best = (di * di + dj * dj, ii, jj)
        return None if best is None else best[1:]

    sa, sb = nearest_ok(ia, ja), nearest_ok(ib, jb)
    if sa is None or sb is None:
        return False
    limit = (math.dist(a, b) + detour_m) / res
    dist = {sa: 0}
    q = deque([sa])
    while q:
        c = q.popleft()
        if c == sb:
            return True
        dc = dist[c]
        if dc > limit:
            continue
        for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            n = (c[0] + di, c[1] + dj)
            if i0 <= n[0] <= i1 and j0 <= n[1] <= j1 and ok[n[1], n[0]] and n not in dist:
                dist[n] = dc + 1
                q.append(n)
    return False


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
