"""The floor-parallax cue (`floorscan.ranging.parallax`) against the simulator's truth: on a
tiled floor driven with the default odometry noise it finds obstacles' bases above grout lines
the edge ranger stops at; on a carpet it leaves the edge ranger's readings as they were; without
poses it is the edge ranger; and bad input is refused in one line. Ranged with the table
calibrated from the simulated pattern, as `floorscan eval` and a user's pipeline range (with
the exact table, which reaches farther, the carpet corridor loses: EVALUATION.md)."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import VisualRanger
from floorscan.errors import ArgumentTypeError, ConfigError, OptionError
from floorscan.evaluation.calibration_error import calibrated_table
from floorscan.evaluation.scoring import score_columns
from floorscan.formats.trajectory import compose
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import Mapper
from floorscan.ranging.parallax import ParallaxRanger
from floorscan.sim import Camera, World, simulate_run


def _run(world: str, seconds: float = 6.0, seed: int = 5):
    cam = Camera()
    run = simulate_run(World.builtin(world), camera=cam, seconds=seconds, seed=seed)
    return cam, run


def _wrong_shares(world: str):
    """Share of columns wrong (status, or > 10 cm from the true base) over the frames where
    the cue has an earlier frame to compare with: edge ranger alone, with the cue."""
    cam, run = _run(world)
    table, _ = calibrated_table(cam, calibration=Config().calibration.kwargs())
    edge = VisualRanger(table, columns=64)
    cued = ParallaxRanger(VisualRanger(table, columns=64))
    mount = tuple(run.camera.robot_from_camera)
    wrong = {"edge": [0, 0], "parallax": [0, 0]}
    compared = 0
    for k in range(len(run)):
        pose = compose(tuple(run.odometry[k]), mount)
        with_cue = cued.scan(run.images[k], timestamp=run.timestamps[k], world_from_camera=pose)
        if cued.last_report["baseline_m"] == 0.0:
            continue
        compared += 1
        truth = run.frame_truth(k)
        for name, scan in (("edge", edge.scan(run.images[k])), ("parallax", with_cue)):
            s = score_columns(scan, truth.status, truth.points)
            wrong[name][0] += int(s.wrong.sum())
            wrong[name][1] += s.wrong.size
    assert compared > len(run) // 2
    return {k: w / n for k, (w, n) in wrong.items()}


def test_on_tiles_the_cue_finds_bases_above_the_grout_lines():
    shares = _wrong_shares("tiles")
    assert shares["edge"] > 0.8  # the grout lines stop the edge ranger (test_sim_ranging)
    assert shares["parallax"] < shares["edge"] - 0.1


def test_on_carpet_the_cue_leaves_the_edge_rangers_readings():
    shares = _wrong_shares("corridor")
    assert shares["parallax"] <= shares["edge"] + 0.01


def test_without_poses_the_cue_is_the_edge_ranger():
    cam, run = _run("tiles", seconds=1.0)
    table = cam.ground_table(spacing_px=4)
    edge = VisualRanger(table, columns=32)
    cued = ParallaxRanger(VisualRanger(table, columns=32))
    for k in range(len(run)):
        a, b = edge.scan(run.images[k]), cued.scan(run.images[k])
        assert np.array_equal(a.status_codes, b.status_codes)
        assert np.array_equal(a.rows, b.rows, equal_nan=True)
        assert cued.last_report["vetoes"] == 0


def test_the_config_turns_it_on_for_the_pipeline_and_only_over_the_edge_ranger():
    cam, run = _run("tiles", seconds=3.0)
    table = cam.ground_table(spacing_px=4)
    cfg = Config().with_overrides({"parallax.enabled": True, "slam.mode": "off"})
    mapper = Mapper(table, cfg, robot_from_camera=tuple(run.camera.robot_from_camera))
    assert isinstance(mapper.parallax, ParallaxRanger)
    vetoes = 0
    for k in range(len(run)):
        mapper.process(run.images[k], timestamp=run.timestamps[k], pose=tuple(run.odometry[k]))
        vetoes += mapper.parallax.last_report["vetoes"]
    assert vetoes > 0
    assert Mapper(table, Config()).parallax is None
    with pytest.raises(ConfigError, match="edge ranger"):
        Mapper(table, cfg.with_overrides({"ranger.kind": "fused"}))


def test_bad_input_is_refused_in_one_line():
    cam = Camera()
    table = cam.ground_table(spacing_px=8)
    with pytest.raises(ArgumentTypeError):
        ParallaxRanger(table)
    with pytest.raises(OptionError, match="min_baseline_m"):
        ParallaxRanger(VisualRanger(table), min_baseline_m=-1.0)
    with pytest.raises(OptionError, match="history_frames"):
        ParallaxRanger(VisualRanger(table), history_frames=1000)
    cued = ParallaxRanger(VisualRanger(table))
    image = np.zeros((table.image_height, table.image_width), np.uint8)
    for pose in [(0.0, 0.0), (float("nan"), 0.0, 0.0), ("a", 0, 0)]:
        with pytest.raises(OptionError, match="world_from_camera"):
            cued.scan(image, world_from_camera=pose)
    with pytest.raises(OptionError, match="parallax"):
        Config().with_overrides({"parallax.max_vetoes": 0})


def test_a_robot_turning_on_the_spot_compares_frames_once_its_camera_has_moved():
    # the simulator's camera sits 0.12 m ahead of the axis the robot turns about: its centre
    # moves along a circle, 2 r sin(turn / 2) (the chord) from where it was; the cue compares
    # with the kept frame farthest away once that reaches min_turn_baseline_m
    from floorscan.sim import render_image

    cam = Camera()
    world = World.builtin("tiles")
    mount = tuple(cam.robot_from_camera)
    r = float(np.hypot(mount[0], mount[1]))
    table = cam.ground_table(spacing_px=8)
    step = 0.1
    for turn_baseline, compared in [(0.05, True), (0.15, False)]:
        cued = ParallaxRanger(VisualRanger(table, columns=32), min_turn_baseline_m=turn_baseline)
        x, y, yaw = world.start
        baselines = []
        for k in range(8):
            pose = (x, y, yaw + step * k)
            image = render_image(world, cam, pose, frame=k)
            cued.scan(image, timestamp=0.1 * k, world_from_camera=compose(pose, mount))
            baselines.append(cued.last_report["baseline_m"])
        chords = [2 * r * np.sin(step * k / 2) for k in range(8)]
        expected = [
            c if compared and k > 0 and c >= turn_baseline else 0.0 for k, c in enumerate(chords)
        ]
        assert baselines == pytest.approx(expected, abs=1e-9)
        assert any(b > 0 for b in baselines) == compared
    with pytest.raises(OptionError, match="min_turn_baseline_m"):
        ParallaxRanger(VisualRanger(table), min_turn_baseline_m=0.2)
    cfg = Config().with_overrides({"parallax.enabled": True, "parallax.min_turn_baseline_m": 0.07})
    assert cfg.parallax.min_turn_baseline_m == 0.07


def test_near_bases_the_edge_ranger_finds_stay():
    # a carpet corridor passed through a doorway: every boundary is an obstacle's base, so a
    # boundary the cue moves away from a right one is a base lost (at a doorway's corners the
    # line through two neighbours' bases follows neither face: floor must beat each face)
    cam = Camera()
    run = simulate_run(World.builtin("corridor"), camera=cam, seconds=20.0, seed=3)
    table, _ = calibrated_table(cam, calibration=Config().calibration.kwargs())
    edge = VisualRanger(table)
    cued = ParallaxRanger(VisualRanger(table))
    mount = tuple(run.camera.robot_from_camera)
    right = kept = 0
    for k in range(len(run)):
        pose = compose(tuple(run.odometry[k]), mount)
        with_cue = cued.scan(run.images[k], timestamp=run.timestamps[k], world_from_camera=pose)
        plain = edge.scan(run.images[k])
        cols = plain.columns.astype(np.intp)
        truth = run.frame_truth(k)
        points = truth.points[cols]
        near = (truth.status[cols] == 0) & (np.hypot(points[:, 0], points[:, 1]) < 1.0)

        found = [
            near & (s.status_codes == 0) & (np.hypot(s.x - points[:, 0], s.y - points[:, 1]) < 0.1)
            for s in (plain, with_cue)
        ]
        right += int(found[0].sum())
        kept += int((found[0] & found[1]).sum())
    assert right > 1000
    assert kept >= 0.97 * right, (kept, right)
