"""A costmap with inflation (ROS costmap_2d's inflation layer) and a navigation function over
it (the wavefront/Dijkstra potential of ROS navfn), from the avoidance map.

Costs follow costmap_2d: 254 lethal (an occupied cell), 253 inscribed (the robot's centre
there puts its footprint on an obstacle), and beyond the inscribed radius
252 exp(-cost_scaling_factor (d - inscribed_radius)) up to ``inflation_radius_m``.
Unknown cells cost nothing (the local costmap's ``track_unknown_space: false``).
"""

from __future__ import annotations

import numpy as np

from .._native.drive import coarse_grid, geodesic_distances
from ..options import OptionsObject

LETHAL = 254
INSCRIBED = 253


class CostmapOptions(OptionsObject, kind="costmap"):
    """The costmap's options: the core's ``CostmapOptions`` (defaults, reasons and rules in
    ``crates/floorscan-core/src/navigation/costmap_options.rs``; ``floorscan.options.
    field_docs("costmap")``): ``robot_radius_m``, ``footprint_padding_m``,
    ``inflation_radius_m``, ``cost_scaling_factor``, ``plan_cell_m``, ``goal_seed_radius_m``,
    ``unknown_cost``. Keyword arguments are any of them (a bad one is an OptionError naming
    it); read-only, ``replace(**changes)`` makes a changed copy.

    >>> CostmapOptions().robot_radius_m
    0.18
    """

    __slots__ = ()


def inflate(occupied: np.ndarray, cell_size_m: float, options: CostmapOptions) -> np.ndarray:
    """(H, W) uint8 costs from a boolean occupied mask."""
    import cv2

    if not occupied.any():
        return np.zeros(occupied.shape, np.uint8)
    occupied = np.asarray(occupied, bool)
    free = (~occupied).view(np.uint8) * np.uint8(255)
    d = cv2.distanceTransform(free, cv2.DIST_L2, 5) * np.float32(cell_size_m)
    # float32 throughout (the band's costs are float32 already): the same costs once truncated
    cost = np.zeros(occupied.shape, np.float32)
    r_in = options.robot_radius_m + options.footprint_padding_m
    band = (d > r_in) & (d <= options.inflation_radius_m)
    cost[band] = 252.0 * np.exp(-options.cost_scaling_factor * (d[band] - r_in))
    cost[d <= r_in] = INSCRIBED
    cost[occupied] = LETHAL
    return cost.astype(np.uint8)


def navigation_function(
    cost: np.ndarray, cell_size_m: float, origin_m, goal_xy, options, known=None
):
    """Geodesic cost-to-goal [m] over the costmap at ``plan_cell_m``, as a function
    f(x, y) of world points (arrays) [m]. Coarse cells all of whose cells are at or above INSCRIBED are impassable; a
    cell's step costs its length times (1 + cost / 64) (navfn's neutral cost of 50 over
    lethal 253, rounded). A goal outside the window (or blocked) is reached through the
    window's border: each border cell starts at its straight-line distance to the goal."""
    f = max(1, int(round(options.plan_cell_m / cell_size_m)))
    step = f * cell_size_m
    # optimistic: a coarse cell is passable when any of its cells is (the dynamic window
    # checks every trajectory on the fine costmap); it costs its cells' mean, and unknown
    # space costs more to plan through than floor seen free (navfn's allow_unknown with a
    # penalty): detours through unseen rooms lose to known floor (in the Rust core)
    blocked, weight = coarse_grid(
        np.ascontiguousarray(cost, np.uint8),
        f,
        INSCRIBED,
        float(options.unknown_cost),
        None if known is None else np.ascontiguousarray(known, bool),
    )
    h, w = blocked.shape
    ox, oy = origin_m
    gx, gy = goal_xy
    gi, gj = int((gx - ox) // step), int((gy - oy) // step)
    jj, ii = np.nonzero(~blocked)
    cx, cy = ox + (ii + 0.5) * step, oy + (jj + 0.5) * step
    d0 = np.hypot(cx - gx, cy - gy)
    if 0 <= gi < w and 0 <= gj < h:
        # the goal's cell, or (when the map blocks it) the free cells around it
        sel = d0 <= max(d0.min() if d0.size else 0.0, step) + 1e-9
        if not (d0.size and d0.min() <= options.goal_seed_radius_m):
            sel = np.zeros(d0.shape, bool)
    else:
        sel = (ii == 0) | (ii == w - 1) | (jj == 0) | (jj == h - 1)
    cells = (jj[sel] * w + ii[sel]).astype(np.int64)
    dist = geodesic_distances(
        np.ascontiguousarray(blocked), np.ascontiguousarray(weight), cells, d0[sel], step
    )

    return NavigationFunction(dist, (float(ox), float(oy)), float(step))


class NavigationFunction:
    """The navigation function's geodesic costs [m] on its coarse grid (``distances`` (h, w),
    cell (0, 0)'s corner at ``origin_m``, cells ``step_m`` wide); called with world points
    (arrays) [m] it returns their cells' costs, ``inf`` outside the grid or where unreached."""

    def __init__(self, distances: np.ndarray, origin_m, step_m: float) -> None:
        self.distances = np.ascontiguousarray(distances, np.float64)
        self.origin_m = origin_m
        self.step_m = step_m

    def __call__(self, x, y) -> np.ndarray:
        h, w = self.distances.shape
        i = np.floor((np.asarray(x) - self.origin_m[0]) / self.step_m).astype(np.int64)
        j = np.floor((np.asarray(y) - self.origin_m[1]) / self.step_m).astype(np.int64)
        inside = (i >= 0) & (i < w) & (j >= 0) & (j < h)
        out = np.full(np.shape(i), np.inf)
        out[inside] = self.distances[j[inside], i[inside]]
        return out
