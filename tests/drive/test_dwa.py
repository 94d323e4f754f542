"""The dynamic window's way out of local minima, on hand-made costmaps: a robot inside an
inflated cell moves to cheaper cells without touching a lethal one; a robot facing a wall with
its goal behind turns instead of standing still."""

from __future__ import annotations

import math

import numpy as np
from floorscan.drive import (
    CostmapOptions,
    DwaOptions,
    choose_velocity,
    inflate,
    navigation_function,
)
from floorscan.drive.costmap import INSCRIBED, LETHAL

CELL = 0.05


def _wall_map():
    """A 4 x 4 m window (origin 0, 0) with a wall along x = 2.0 m (cells 40-41)."""
    occ = np.zeros((80, 80), bool)
    occ[:, 40:42] = True
    return occ


def test_inside_an_inflated_cell_the_robot_backs_away_from_the_wall():
    opts = CostmapOptions()
    cost = inflate(_wall_map(), CELL, opts)
    pose = (1.82, 2.0, 0.0)  # 18 cm from the wall, facing it: inscribed
    assert cost[40, 36] >= INSCRIBED
    goal = (0.5, 2.0)
    nav = navigation_function(cost, CELL, (0.0, 0.0), goal, opts)
    dwa = DwaOptions()
    x, y, th = pose
    velocity = (0.0, 0.0)
    for _ in range(60):  # 6 s at 10 Hz, integrated exactly (unicycle)
        v, w, _ = choose_velocity((x, y, th), velocity, cost, (0, 0), CELL, nav, goal, 0.1, dwa)
        i, j = int(x / CELL), int(y / CELL)
        assert cost[j, i] < LETHAL
        x, y, th = (
            x + v * 0.1 * math.cos(th + w * 0.05),
            y + v * 0.1 * math.sin(th + w * 0.05),
            th + w * 0.1,
        )
        velocity = (v, w)
    assert x < 1.82 - 0.1  # it left the wall behind, towards its goal
    assert cost[int(y / CELL), int(x / CELL)] < INSCRIBED


def test_facing_a_wall_with_the_goal_behind_the_robot_turns_rather_than_stands():
    opts = CostmapOptions()
    cost = inflate(_wall_map(), CELL, opts)
    pose = (1.45, 2.0, 0.0)  # outside the inscribed band, facing the wall
    goal = (0.3, 2.0)
    nav = navigation_function(cost, CELL, (0.0, 0.0), goal, opts)
    v, w, _ = choose_velocity(pose, (0.0, 0.0), cost, (0, 0), CELL, nav, goal, 0.1, DwaOptions())
    assert abs(w) > 0.2 or v > 0.0
