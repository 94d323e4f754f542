"""Leg recall (issue 13, thin obstacles) against the simulator's truth: readings taken from the
truth itself find every leg in view; no readings find none; readings moved off the legs by
more than the tolerance find none; legs beyond the range limit do not count."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import Scan
from floorscan.evaluation.thin_obstacles import FOUND_TOLERANCE_M, Legs, leg_recall
from floorscan.sim import World, simulate_run

WORLD = """
name = "two chairs"
seed = 1
[start]
x = 0.5
y = 0.0
[[walls]]
from = [-1.0, -2.0]
to = [4.0, -2.0]
[[walls]]
from = [4.0, -2.0]
to = [4.0, 2.0]
[[walls]]
from = [4.0, 2.0]
to = [-1.0, 2.0]
[[walls]]
from = [-1.0, 2.0]
to = [-1.0, -2.0]
[[chairs]]
center = [1.45, 0.0]
[[tables]]
center = [3.0, 0.0]
size = [0.8, 0.6]
"""


@pytest.fixture(scope="module")
def standing_run():
    world = World.from_toml(WORLD)
    run = simulate_run(world, commands=[(0.5, 0.0, 0.0)], seed=0, labels=False)
    return world, run


def truth_scans(run, shift_m: float = 0.0):
    """One scan per frame with every image column's true boundary point (optionally moved
    ``shift_m`` further away along its ray)."""
    t = run.truth
    scans = []
    for k in range(len(run)):
        x, y = t.points[k][:, 0], t.points[k][:, 1]
        r = np.hypot(x, y)
        scale = np.where(r > 0, (r + shift_m) / np.maximum(r, 1e-9), 1.0)
        scans.append(
            Scan.from_arrays(
                timestamp=float(k),
                columns=np.arange(t.status.shape[1]),
                rows=t.rows[k],
                status=t.status[k],
                x=np.nan_to_num(x * scale),
                y=np.nan_to_num(y * scale),
            )
        )
    return scans


def test_legs_are_the_thin_solids_standing_on_the_floor(standing_run):
    world, _ = standing_run
    legs = Legs.of_world(world)
    # a chair has 4 legs (2.5 cm), a table 4 (5 cm); walls, seats and table tops are not legs
    assert len(legs) == 8
    assert sorted(set(np.round(2 * legs.half_sides, 3))) == [0.025, 0.05]


def test_truth_readings_find_every_leg_in_view_and_nothing_finds_none(standing_run):
    world, run = standing_run
    legs = Legs.of_world(world)
    exact = leg_recall(legs, run.truth, truth_scans(run), within_m=1.0)
    assert exact.seen > 0 and exact.found == exact.seen
    nothing = [
        Scan.from_arrays(
            timestamp=0.0, columns=[0], rows=[0.0], status=["no_boundary"], x=[0.0], y=[0.0]
        )
        for _ in range(len(run))
    ]
    empty = leg_recall(legs, run.truth, nothing, within_m=1.0)
    assert empty.seen == exact.seen and empty.found == 0


def test_readings_off_the_legs_by_more_than_the_tolerance_miss(standing_run):
    world, run = standing_run
    legs = Legs.of_world(world)
    moved = leg_recall(legs, run.truth, truth_scans(run, shift_m=2 * FOUND_TOLERANCE_M + 0.05))
    assert moved.seen > 0 and moved.found == 0


def test_only_legs_within_range_count(standing_run):
    world, run = standing_run
    legs = Legs.of_world(world)
    near = leg_recall(legs, run.truth, truth_scans(run), within_m=1.0)
    far = leg_recall(legs, run.truth, truth_scans(run), within_m=5.0)
    # the chair (1 m ahead of the camera) is within 1 m only in part; the table only at 5 m
    assert far.seen > near.seen > 0
