"""Local scan matching in the pipeline (`[slam]`): judged against the simulator's true poses
and against analytic geometry (a plain corridor constrains the pose across itself, never
along); the config table; `run`'s trajectory files and summary."""

from __future__ import annotations

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest
from floorscan import ConfigError
from floorscan.cli import main
from floorscan.formats.trajectory import read_tum
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import Mapper
from floorscan.pipeline.pose_correction import PoseCorrection, inverse
from floorscan.ranging.scan import ColumnStatus
from floorscan.sim import Camera, OdometryNoise, Robot, World, simulate_run
from synthetic_dataset import camera_table, make_dataset


def _corridor_scan(pose, *, half_width_m=1.0, reach_m=(0.6, 2.6), n=80):
    """The boundary points (robot frame) a forward-looking sensor at ``pose`` sees of two
    endless walls y = +-half_width_m, as a scan-like object (what the matcher reads)."""
    xs = np.linspace(*reach_m, n // 2)
    world = [
        (pose[0] + x, side * half_width_m) for side in (-1.0, 1.0) for x in xs
    ]  # straight ahead along +x (the walls' points at these x)
    c, s = math.cos(pose[2]), math.sin(pose[2])
    rel = [(px - pose[0], py - pose[1]) for px, py in world]
    x = np.array([c * dx + s * dy for dx, dy in rel])
    y = np.array([-s * dx + c * dy for dx, dy in rel])
    codes = np.full(len(x), int(ColumnStatus.BOUNDARY), np.int8)
    return SimpleNamespace(x=x, y=y, status_codes=codes)


def test_a_plain_corridor_corrects_across_itself_and_keeps_odometry_along():
    # analytic: walls at y = +-1 m, the robot drives straight down the middle; odometry reads
    # 5 % long and turns 0.004 rad a 5 cm step that the robot does not (its heading drifts,
    # and so its y); the match knows nothing along the corridor, so the corrected pose keeps
    # odometry's distance driven and loses the heading and the sideways error
    pc = PoseCorrection({"size_m": 20.0, "calibrate_odometry": False})
    odo = (0.0, 0.0, 0.0)
    driven = 0.0
    for k in range(40):
        true = (0.05 * k, 0.0, 0.0)
        if k:
            step = 0.05 * 1.05
            odo = (
                odo[0] + step * math.cos(odo[2]),
                odo[1] + step * math.sin(odo[2]),
                odo[2] + 0.004,
            )
            driven += step
        pose = pc.correct(_corridor_scan(true), odo, timestamp=0.1 * k)
    assert abs(odo[1]) > 0.1 and abs(odo[2]) > 0.15  # odometry has drifted
    assert abs(pose[1]) < 0.03 and abs(pose[2]) < 0.02
    # along: odometry's length error (2.05 m driven for the truth's 1.95 m) mostly stays
    # (only the far ends of the walls seen so far say anything along the corridor)
    true_x = 0.05 * 39
    assert pose[0] - true_x > 0.4 * (driven - true_x)
    assert pc.counts.matched >= 35


def test_inverse_undoes_a_transform():
    from floorscan.formats.trajectory import compose

    p = (1.0, -2.0, 0.7)
    assert compose(p, inverse(p)) == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)


@pytest.fixture(scope="module")
def drifting_corridor():
    robot = Robot(
        odometry=OdometryNoise(
            wheel_sigma_per_sqrt_m=0.03,
            radius_scale_error=0.03,
            radius_difference=0.012,
            wheelbase_error=0.06,
        )
    )
    camera = Camera()
    sim = simulate_run(
        World.builtin("corridor"), camera=camera, robot=robot, seconds=20.0, seed=3, threads=2
    )
    return sim, camera.ground_table(spacing_px=4), tuple(camera.robot_from_camera)


def _placed(mapper, sim):
    out = []
    for k in range(len(sim)):
        mapper.process(
            sim.images[k], timestamp=float(sim.timestamps[k]), pose=tuple(sim.odometry[k])
        )
        out.append(mapper.last_pose)
    return np.asarray(out)


def test_matching_keeps_the_simulated_robot_near_its_true_pose(drifting_corridor):
    sim, table, mount = drifting_corridor
    truth = np.asarray(sim.poses)
    odo_err = np.hypot(*(np.asarray(sim.odometry)[:, :2] - truth[:, :2]).T)
    mapper = Mapper(table, Config(), robot_from_camera=mount)
    est = _placed(mapper, sim)
    err = np.hypot(*(est[:, :2] - truth[:, :2]).T)
    assert odo_err[-1] > 0.3  # the odometry has drifted
    assert err[-1] < 0.1 and err[-1] < 0.25 * odo_err[-1]
    assert np.sqrt(np.mean(err**2)) < 0.5 * np.sqrt(np.mean(odo_err**2))
    assert mapper.slam.counts.matched > len(sim) // 2
    # off: the poses are odometry's, exactly
    plain = Mapper(table, Config.from_dict({"slam": {"mode": "off"}}), robot_from_camera=mount)
    assert plain.slam is None
    np.testing.assert_array_equal(_placed(plain, sim), np.asarray(sim.odometry))


def test_the_slam_table_is_the_rust_options_and_bad_keys_name_themselves():
    cfg = Config.from_toml('[slam]\nmode = "off"\n[slam.matcher]\nmin_points = 60\n')
    assert cfg.slam.mode == "off" and cfg.slam.matcher.min_points == 60
    assert cfg.slam.matcher.size_m == Config().slam.matcher.size_m  # the rest: defaults
    assert Config().slam.mode == "local"
    for text, key in (
        ('[slam]\nmode = "loops"\n', "slam.mode"),
        ("[slam.graph]\nloop_candidates = 0\n", "slam.graph"),
        ("[slam]\nspeed = 1\n", "slam.speed"),
        ("[slam.matcher]\nsize_m = 1.0\n", "slam.matcher"),
    ):
        with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
            Config.from_toml(text)
    assert "slam.mode" in Config().to_toml() or "[slam]" in Config().to_toml()


def test_camera_runs_refuse_the_graph_mode_in_one_line():
    cfg = Config.from_toml('[slam]\nmode = "graph"\n')
    assert cfg.slam.mode == "graph"  # a valid mode: map-log's
    with pytest.raises(ConfigError, match="map-log"):
        Mapper(camera_table(), cfg)


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("ds")
    make_dataset(d / "room", n=30)
    camera_table().save(d / "table.json")
    return d


def _run(dataset, out, *extra):
    args = ["run", str(dataset / "room"), "--table", str(dataset / "table.json")]
    return main([*args, "-o", str(out), "--threshold", "20", *extra])


def test_run_writes_both_trajectories_and_counts_the_matched_frames(dataset, tmp_path):
    assert _run(dataset, tmp_path / "out") == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    slam = summary["slam"]
    assert slam["mode"] == "local"
    assert slam["frames_matched"] + slam["frames_not_matched"] == 30
    odo = read_tum(tmp_path / "out" / "trajectory_odometry.tum")
    corrected = read_tum(tmp_path / "out" / "trajectory.tum")
    assert len(odo) == len(corrected) == 30
    np.testing.assert_array_equal(odo.timestamps, corrected.timestamps)
    # the synthetic dataset's odometry is exact: the correction stays small
    assert np.max(np.hypot(odo.x - corrected.x, odo.y - corrected.y)) < 0.05
    # off: no corrected trajectory
    cfg = tmp_path / "off.toml"
    cfg.write_text('[slam]\nmode = "off"\n')
    assert _run(dataset, tmp_path / "off", "--config", str(cfg)) == 0
    assert not (tmp_path / "off" / "trajectory.tum").exists()
    assert json.loads((tmp_path / "off" / "summary.json").read_text())["slam"] == {"mode": "off"}
