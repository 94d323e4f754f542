"""The README's Python examples are tests (issue 37): every ```python block runs as written,
in order and in one namespace (a later block continues an earlier one, as a reader would), in
a fresh folder holding only what the README says to make first: the simulator's dataset, by
the `floorscan sim` command quoted in the first block. A name used but never defined, a file
the README does not say how to get, a changed signature: each fails here."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import numpy as np
import pytest
from floorscan import Occupancy, OccupancyGrid, VisualRanger
from floorscan.cli import main
from floorscan.formats.dataset import read_images_txt
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import ranger_from_config

README = Path(__file__).resolve().parents[1] / "README.md"


def python_blocks(text: str) -> list:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def sim_command(blocks: list) -> list:
    """The `floorscan sim ...` command a block quotes (in backquotes) as where its files come
    from."""
    found = [c for b in blocks for c in re.findall(r"`(floorscan sim [^`]+)`", b)]
    assert len(found) == 1, found
    return shlex.split(found[0])[1:]


@pytest.fixture(scope="module")
def readme_run(tmp_path_factory):
    """The README's blocks run one after the other in a folder of their own."""
    blocks = python_blocks(README.read_text())
    folder = tmp_path_factory.mktemp("readme")
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(folder)
        assert main(sim_command(blocks)) == 0
        namespace: dict = {"__name__": "readme"}
        after = []
        for k, block in enumerate(blocks):
            exec(compile(block, f"README.md python block {k + 1}", "exec"), namespace)
            after.append({p.name for p in folder.iterdir()})
    return folder, blocks, namespace, after


def test_the_readme_has_python_examples_and_they_all_run(readme_run):
    folder, blocks, namespace, after = readme_run
    assert len(blocks) >= 3  # the front-door example, maps, calibration, simulator
    assert len(after) == len(blocks)


def cell_centres(grid: OccupancyGrid, mask: np.ndarray):
    """World x, y [m] of the cells where ``mask`` (row 0 at the lowest y, nav_msgs layout)."""
    e = grid.extent
    rows, cols = np.nonzero(mask)
    return e.origin_m[0] + (cols + 0.5) * e.cell_size_m, e.origin_m[1] + (
        rows + 0.5
    ) * e.cell_size_m


def test_the_front_door_example_maps_the_simulated_corridor(readme_run):
    folder, blocks, namespace, after = readme_run
    assert {"map.yaml", "map.pgm", "table.json"} <= after[0]
    frames = read_images_txt(folder / "corridor-run")
    assert namespace["frame"].timestamp == frames[-1].timestamp  # every frame went through
    grid = OccupancyGrid.load(folder / "map.yaml")
    truth = OccupancyGrid.load(folder / "corridor-run" / "truth" / "map.yaml")  # the simulator's
    classes = grid.occupancy_classes()
    occupied = cell_centres(grid, classes == Occupancy.OCCUPIED)
    free = cell_centres(grid, classes == Occupancy.FREE)
    assert occupied[0].size > 100 and free[0].size > 1000
    # walls where the true walls are (odometry drifts a little in 10 s), floor where the floor is
    assert (truth.distance_to_nearest_occupied(*occupied) < 0.1).mean() > 0.9
    assert truth.is_free(*free).mean() > 0.95


def test_the_readme_ranger_is_the_edge_ranger_the_default_kind(readme_run):
    folder, blocks, namespace, after = readme_run
    ranger = namespace["ranger"]
    assert isinstance(ranger, VisualRanger)
    assert "edge ranger" in blocks[0] and "VisualRanger" in blocks[0]
    # what the comment says: the configuration's default kind and `floorscan scan`'s ranger
    assert Config().ranger.kind == "edge"
    assert isinstance(ranger_from_config(namespace["table"], Config()), VisualRanger)
