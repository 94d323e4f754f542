"""The map builder on the simulator's corridor: with true poses, the cells the map calls known
agree with the world's true occupancy. Needs ``floorscan.sim`` (the simulator); skipped with a
reason where this build does not have it."""

import floorscan
import numpy as np
import pytest

sim = pytest.importorskip(
    "floorscan.sim", reason="floorscan.sim (the simulator) is not in this build"
)


def simulator_api():
    missing = [n for n in ("World", "simulate_run") if not hasattr(sim, n)]
    if missing:
        pytest.skip(f"floorscan.sim lacks {missing}: the simulator API this test uses has changed")
    return sim.World, sim.simulate_run


def test_corridor_map_agrees_with_the_true_occupancy():
    World, simulate_run = simulator_api()
    world = World.builtin("corridor")
    run = simulate_run(world, seconds=40.0, seed=3, labels=False, truth=False)
    camera = run.camera
    ranger = floorscan.VisualRanger(camera.ground_table(spacing_px=4, max_range_m=4.0), columns=64)
    grid = floorscan.OccupancyGrid(cell_size_m=0.04)
    for image, pose in zip(run.images, run.poses):
        grid.insert_scan(ranger.scan(image), pose, camera.robot_from_camera)

    truth = world.occupancy(resolution_m=0.02)
    classes = grid.occupancy_classes()
    e = grid.extent
    iy, ix = np.nonzero(classes != 1)
    xs = e.origin_m[0] + (ix + 0.5) * e.cell_size_m
    ys = e.origin_m[1] + (iy + 0.5) * e.cell_size_m
    true = np.array([truth.value_at(x, y) for x, y in zip(xs, ys)])
    ours = np.where(classes[iy, ix] == 2, sim.OCCUPIED, sim.FREE)
    agree = np.mean(ours == true)
    assert len(xs) > 2000, f"the map should know many cells, got {len(xs)}"
    assert agree >= 0.97, f"{agree:.4f} of {len(xs)} known cells agree with the truth"
