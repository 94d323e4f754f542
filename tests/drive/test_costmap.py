"""The costmap's navigation function against analytic geometry: on an open grid it is the
octile distance to the goal's cell; behind a wall it goes round the wall's end."""

from __future__ import annotations

import math

import numpy as np
import pytest
from floorscan.drive import CostmapOptions, navigation_function

CELL = 0.05


def test_an_open_grid_gives_the_octile_distance_to_the_goal():
    opts = CostmapOptions()  # plan cells of 0.1 m: 2 x 2 map cells
    cost = np.zeros((60, 60), np.uint8)
    goal = (0.55, 0.55)  # centre of plan cell (5, 5)
    nav = navigation_function(cost, CELL, (0.0, 0.0), goal, opts)
    for i, j in [(5, 5), (12, 5), (5, 20), (20, 27), (0, 29)]:
        di, dj = abs(i - 5), abs(j - 5)
        octile = 0.1 * (max(di, dj) - min(di, dj) + math.sqrt(2) * min(di, dj))
        x, y = (i + 0.5) * 0.1, (j + 0.5) * 0.1
        assert float(nav(np.array([x]), np.array([y]))[0]) == pytest.approx(octile, abs=1e-9)


def test_a_wall_is_gone_round_not_through():
    opts = CostmapOptions()
    cost = np.zeros((60, 60), np.uint8)
    cost[:50, 30:32] = 254  # a wall at x = 1.5 m from y = 0 to 2.5 m; open above
    nav = navigation_function(cost, CELL, (0.0, 0.0), (2.55, 0.25), opts)
    straight = 2.0
    d = float(nav(np.array([0.55]), np.array([0.25]))[0])
    assert d > straight + 3.0  # round the end at y = 2.5 m: about 5.4 m (octile)
    assert math.isinf(float(nav(np.array([1.55]), np.array([1.0]))[0]))  # inside the wall
