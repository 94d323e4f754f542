"""The dynamic window approach (Fox, Burgard & Thrun 1997) as ROS's dwa_local_planner runs it:
sample velocities (v, omega) reachable within one control period from the current ones,
roll each out at constant velocity for ``sim_time_s``, drop those whose path enters an
inscribed or lethal costmap cell, and take the cheapest of

    path_distance_bias * nav(forward point) + goal_distance_bias * nav(end)
    + occdist_scale * (largest cost along the path)

where nav is the navigation function [cells] and the forward point lies
``forward_point_distance_m`` ahead of the rolled-out end pose. When no sample is admissible
or the best one stands still (a local minimum of the scores: facing a wall with the way on
in another direction, or with the robot already inside an inflated cell after drift), the
robot escapes as move_base's recovery would, but without waiting: it looks along 36 headings
for a short straight move that the costmap allows (inside an inflated cell: one that never
touches a lethal cell and ends in a cheaper one), turns towards the one whose end is lowest
on the navigation function (or, where the plan reaches none, the most open one), and drives
off slowly once facing it.
Within two forward-point distances of the goal both terms use the straight-line distance of
the end point to the goal, so the robot settles on it instead of circling.
"""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np

from .._native.drive import best_velocity_sample
from ..options import OptionsObject
from .costmap import INSCRIBED, LETHAL, NavigationFunction


class DwaOptions(OptionsObject, kind="dwa"):
    """The dynamic window's options: the core's ``DwaOptions`` (defaults, dwa_local_planner's
    unless said, reasons and rules in ``crates/floorscan-core/src/navigation/dwa_options.rs``;
    ``floorscan.options.field_docs("dwa")``): ``max_speed_m_s``, ``max_turn_rad_s``,
    ``acc_lim_x``, ``acc_lim_theta``, ``sim_time_s``, ``sim_granularity_m``, ``vx_samples``,
    ``vth_samples``, ``path_distance_bias``, ``goal_distance_bias``, ``occdist_scale``,
    ``forward_point_distance_m``, ``blind_radius_m``. Keyword arguments are any of them (a bad
    one is an OptionError naming it); read-only, ``replace(**changes)`` makes a changed copy.

    >>> DwaOptions(max_speed_m_s=0.5).max_speed_m_s, DwaOptions().vth_samples
    (0.5, 21)
    """

    __slots__ = ()


def velocity_samples(velocity: Tuple[float, float], dt_s: float, options: DwaOptions):
    """(speeds (n_v,), turn rates (n_w,), roll-out times (n_t,)) of the window reachable within
    ``dt_s`` from ``velocity`` (v [m/s], omega [rad/s])."""
    o = options
    v0, w0 = velocity
    vs = np.linspace(
        max(0.0, v0 - o.acc_lim_x * dt_s),
        min(o.max_speed_m_s, v0 + o.acc_lim_x * dt_s),
        o.vx_samples,
    )
    ws = np.linspace(
        max(-o.max_turn_rad_s, w0 - o.acc_lim_theta * dt_s),
        min(o.max_turn_rad_s, w0 + o.acc_lim_theta * dt_s),
        o.vth_samples,
    )
    steps = max(2, int(math.ceil(o.max_speed_m_s * o.sim_time_s / o.sim_granularity_m)))
    t = np.linspace(o.sim_time_s / steps, o.sim_time_s, steps)
    return vs, ws, t


def choose_velocity(
    pose: Tuple[float, float, float],
    velocity: Tuple[float, float],
    cost: np.ndarray,
    origin_m,
    cell_size_m: float,
    nav: NavigationFunction,
    goal_xy,
    dt_s: float,
    options: DwaOptions,
    unknown: Optional[np.ndarray] = None,
) -> Tuple[float, float, bool]:
    """(v [m/s], omega [rad/s], admissible) for the next control period ``dt_s`` [s].
    ``nav``: :func:`~floorscan.drive.costmap.navigation_function`'s result; ``unknown``: (H, W)
    bool, the cells without evidence (see ``blind_radius_m``). The roll-outs and scores run in
    the Rust core (``floorscan_core::dynamic_window``)."""
    o = options
    vs, ws, t = velocity_samples(velocity, dt_s, o)
    k = best_velocity_sample(
        tuple(float(p) for p in pose),
        vs,
        ws,
        t,
        np.ascontiguousarray(cost, np.uint8),
        (float(origin_m[0]), float(origin_m[1])),
        float(cell_size_m),
        None if unknown is None else np.ascontiguousarray(unknown, bool),
        nav.distances,
        nav.origin_m,
        nav.step_m,
        (float(goal_xy[0]), float(goal_xy[1])),
        (
            o.path_distance_bias,
            o.goal_distance_bias,
            o.occdist_scale,
            o.forward_point_distance_m,
            o.blind_radius_m,
        ),
        INSCRIBED,
    )
    if k is not None:
        v, w = float(vs[k % len(vs)]), float(ws[k // len(vs)])
        if v > 1e-3:
            return v, w, True
    v, w = escape(pose, cost, origin_m, cell_size_m, nav, goal_xy, options)
    return v, w, False


ESCAPE_HEADINGS = 36
ESCAPE_REACH_M = 0.4
ESCAPE_SPEED_M_S = 0.15


def _cost_at(cost: np.ndarray, origin_m, cell_size_m: float, x, y) -> np.ndarray:
    """Values of a grid (costs, or a mask) at world points [m]; 0 outside the window
    (unknown, as the costmap's)."""
    h, w = cost.shape
    ci = np.floor((np.asarray(x) - origin_m[0]) / cell_size_m).astype(np.int64)
    cj = np.floor((np.asarray(y) - origin_m[1]) / cell_size_m).astype(np.int64)
    inside = (ci >= 0) & (ci < w) & (cj >= 0) & (cj < h)
    c = np.zeros(np.shape(ci), np.float64)
    c[inside] = cost[cj[inside], ci[inside]]
    return c


def escape(pose, cost, origin_m, cell_size_m: float, nav, goal_xy, options: DwaOptions):
    """(v, omega) out of a local minimum: towards the best of ``ESCAPE_HEADINGS`` straight
    moves of ``ESCAPE_REACH_M`` the costmap allows (see the module's docstring)."""
    x0, y0, th0 = pose
    heads = th0 + np.linspace(-math.pi, math.pi, ESCAPE_HEADINGS, endpoint=False)
    r = np.arange(1, 9) * (ESCAPE_REACH_M / 8)
    px = x0 + r[None, :] * np.cos(heads)[:, None]
    py = y0 + r[None, :] * np.sin(heads)[:, None]
    c = _cost_at(cost, origin_m, cell_size_m, px, py)
    here = float(_cost_at(cost, origin_m, cell_size_m, x0, y0))
    if here < INSCRIBED:
        passable = c.max(axis=1) < INSCRIBED
    else:  # already in an inflated cell: never touch a lethal one, end somewhere cheaper
        passable = (c.max(axis=1) < LETHAL) & (c[:, -1] < here)
    if not passable.any():
        return 0.0, min(options.max_turn_rad_s, 0.6)
    n_end = np.asarray(nav(px[:, -1], py[:, -1]), np.float64)
    reach = passable & np.isfinite(n_end)
    if reach.any():
        k = int(np.argmin(np.where(reach, n_end, np.inf)))
    else:  # the plan reaches none of them: the most open, then the nearest to the goal
        d = np.hypot(px[:, -1] - goal_xy[0], py[:, -1] - goal_xy[1])
        k = int(np.argmin(np.where(passable, c[:, -1] * 1e3 + d, np.inf)))
    err = math.remainder(float(heads[k]) - th0, 2 * math.pi)
    w = max(-options.max_turn_rad_s, min(options.max_turn_rad_s, 2.0 * err))
    if abs(err) > 0.3:
        return 0.0, w
    return min(ESCAPE_SPEED_M_S, options.max_speed_m_s), w
