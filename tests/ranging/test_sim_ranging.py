"""The simulator against floorscan's own visual range sensor, with the exact ground table: the
ranger finds the true boundary on carpet, stops early at paper and linoleum (the appearance
boundary, as the paper's robot did), and fails on tiles (the texture assumption). A check that
images, labels and the image-to-ground mapping are registered, and that the worlds test the
edge filter honestly."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import VisualRanger
from floorscan.sim import Camera, World, simulate_run


def ranger_vs_truth(world: str):
    """Per boundary column found by the ranger where the truth has a boundary: (found row,
    true boundary row, true appearance row)."""
    cam = Camera()
    run = simulate_run(World.builtin(world), camera=cam, seconds=6.0, seed=2, labels=False)
    ranger = VisualRanger(cam.ground_table(spacing_px=4), columns=64)
    found, rows, appearance = [], [], []
    for k in range(0, len(run), 3):
        scan = ranger.scan(run.images[k], timestamp=run.timestamps[k])
        both = (scan.status == "boundary") & (run.truth.status_names[k][scan.columns] == "boundary")
        found.extend(scan.rows[both])
        rows.extend(run.truth.rows[k][scan.columns[both]])
        appearance.extend(run.truth.appearance_rows[k][scan.columns[both]])
    return np.array(found), np.array(rows), np.array(appearance)


def test_on_carpet_the_ranger_finds_the_true_boundary():
    found, rows, _ = ranger_vs_truth("corridor")
    assert len(found) > 500
    err = found - rows
    assert np.median(np.abs(err)) < 0.5
    assert (np.abs(err) < 1.5).mean() > 0.85


def test_paper_and_linoleum_stop_the_ranger_at_the_appearance_boundary():
    found, rows, appearance = ranger_vs_truth("lab")
    early = found - rows > 3.0  # rows grow downwards: found nearer than the obstacle
    assert early.mean() > 0.05
    # Those early points are the appearance boundary (paper, linoleum threshold).
    assert np.median(np.abs(found[early] - appearance[early])) < 1.0


@pytest.mark.parametrize("world", ["tiles"])
def test_tiles_break_the_texture_assumption(world):
    found, rows, _ = ranger_vs_truth(world)
    assert (found - rows > 3.0).mean() > 0.5
