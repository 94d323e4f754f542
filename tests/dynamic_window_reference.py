"""The dynamic window's roll-outs and scores as first written with numpy: the reference the
Rust core (``floorscan_core::dynamic_window``) must equal (tests/drive/test_dynamic_window.py).
Returns the chosen sample's (v, omega), or None where ``choose_velocity`` escapes."""

from __future__ import annotations

import math

import numpy as np
from floorscan.drive.costmap import INSCRIBED
from floorscan.drive.dwa import _cost_at, velocity_samples


def reference_choice(
    pose, velocity, cost, origin_m, cell_size_m, nav, goal_xy, dt_s, o, unknown=None
):
    vs, ws, t = velocity_samples(velocity, dt_s, o)
    V, W = (a.ravel() for a in np.meshgrid(vs, ws))
    x0, y0, th0 = pose
    th = th0 + W[:, None] * t[None, :]
    small = np.abs(W) < 1e-6
    Wsafe = np.where(small, 1.0, W)
    xs = np.where(
        small[:, None],
        x0 + V[:, None] * t * math.cos(th0),
        x0 + (V / Wsafe)[:, None] * (np.sin(th) - math.sin(th0)),
    )
    ys = np.where(
        small[:, None],
        y0 + V[:, None] * t * math.sin(th0),
        y0 - (V / Wsafe)[:, None] * (np.cos(th) - math.cos(th0)),
    )
    worst = _cost_at(cost, origin_m, cell_size_m, xs, ys).max(axis=1)
    ok = worst < INSCRIBED
    if unknown is not None:
        beyond = np.hypot(xs - x0, ys - y0) > o.blind_radius_m
        unseen = _cost_at(unknown, origin_m, cell_size_m, xs, ys) > 0
        ok &= ~(unseen & beyond).any(axis=1)
    ex, ey, eth = xs[:, -1], ys[:, -1], th[:, -1]
    fx = ex + o.forward_point_distance_m * np.cos(eth)
    fy = ey + o.forward_point_distance_m * np.sin(eth)
    n_end, n_fwd = nav(ex, ey), nav(fx, fy)
    far = 1e3
    n_end = np.where(np.isfinite(n_end), n_end, far + np.hypot(ex - goal_xy[0], ey - goal_xy[1]))
    n_fwd = np.where(np.isfinite(n_fwd), n_fwd, far + np.hypot(fx - goal_xy[0], fy - goal_xy[1]))
    if math.hypot(x0 - goal_xy[0], y0 - goal_xy[1]) < o.forward_point_distance_m * 2:
        n_end = np.where(
            np.isfinite(nav(ex, ey)), np.hypot(ex - goal_xy[0], ey - goal_xy[1]), n_end
        )
        n_fwd = n_end
    score = (
        o.path_distance_bias * n_fwd / cell_size_m
        + o.goal_distance_bias * n_end / cell_size_m
        + o.occdist_scale * worst
    )
    if not ok.any():
        return None
    k = int(np.argmin(np.where(ok, score, np.inf)))
    return float(V[k]), float(W[k])
