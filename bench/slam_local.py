"""Local scan matching in the pipeline, side by side with odometry alone (issue 38, step 1).

Simulates a world (built-in name or a TOML file such as bench/worlds/office_l.toml) with the
given odometry noise, ranges every frame with the calibrated table (as `floorscan eval` does),
and maps it once per variant of the config: scores of the map against the true occupancy and
the pose error against the simulator's truth.

    .venv/bin/python bench/slam_local.py corridor --seconds 60 --odometry default \
        --variant off slam.mode=off --variant local

A variant is a name followed by dotted config overrides (``slam.matcher.min_points=60``).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
from floorscan.evaluation.calibration_error import calibrated_table
from floorscan.evaluation.demo import SIMULATION_CONFIG
from floorscan.evaluation.scenarios import ODOMETRY
from floorscan.evaluation.scoring import score_map
from floorscan.pipeline.mapper import Mapper
from floorscan.sim import Camera, OdometryNoise, Robot, World, simulate_run


def parse_value(text: str):
    for convert in (int, float):
        try:
            return convert(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text, text)


def pose_errors(est: np.ndarray, truth: np.ndarray):
    d = np.hypot(est[:, 0] - truth[:, 0], est[:, 1] - truth[:, 1])
    dyaw = np.abs(np.remainder(est[:, 2] - truth[:, 2] + math.pi, 2 * math.pi) - math.pi)
    return float(d[-1]), float(d.max()), float(np.sqrt(np.mean(d**2))), float(dyaw.max())


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("world", help="built-in world name or a world TOML file")
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--odometry", default="default", choices=sorted(ODOMETRY))
    p.add_argument("--table", default="calibrated", choices=["calibrated", "exact"])
    p.add_argument(
        "--variant", nargs="+", action="append", metavar=("NAME", "KEY=VALUE"), default=None
    )
    a = p.parse_args()
    variants = a.variant or [["off", "slam.mode=off"], ["local"]]
    world = World.load(a.world) if Path(a.world).suffix == ".toml" else World.builtin(a.world)
    wheel, scale, radius, base = ODOMETRY[a.odometry]
    robot = Robot(
        odometry=OdometryNoise(
            wheel_sigma_per_sqrt_m=wheel,
            radius_scale_error=scale,
            radius_difference=radius,
            wheelbase_error=base,
        )
    )
    camera = Camera()
    t0 = time.perf_counter()
    sim = simulate_run(world, camera=camera, robot=robot, seconds=a.seconds, seed=a.seed, threads=2)
    base_cfg = SIMULATION_CONFIG()
    if a.table == "exact":
        table = camera.ground_table(spacing_px=base_cfg.calibration.spacing_px)
    else:
        table, _ = calibrated_table(camera, calibration=base_cfg.calibration.kwargs())
    raster = world.occupancy(resolution_m=base_cfg.grid.cell_size_m)
    mount = tuple(camera.robot_from_camera)
    truth = np.asarray(sim.poses, np.float64)
    print(
        f"{world.name}, {len(sim)} frames, odometry {a.odometry}, seed {a.seed}: "
        f"simulated in {time.perf_counter() - t0:.1f} s; odometry's final error "
        f"{pose_errors(np.asarray(sim.odometry), truth)[0]:.3f} m"
    )
    print(
        "| variant | agreement | occ. precision | occ. recall | matched | final / max / rms "
        "pose error [m] | max yaw error [rad] | matching ms/frame |"
    )
    print("|---|---:|---:|---:|---:|---|---:|---:|")
    for name, *sets in variants:
        overrides = dict(s.split("=", 1) for s in sets)
        cfg = base_cfg.with_overrides({k: parse_value(v) for k, v in overrides.items()})
        mapper = Mapper(table, cfg, robot_from_camera=mount)
        est = []
        for k in range(len(sim)):
            mapper.process(
                sim.images[k], timestamp=float(sim.timestamps[k]), pose=tuple(sim.odometry[k])
            )
            est.append(mapper.last_pose)
        g = mapper.global_map
        s = score_map(
            g.occupancy_classes(),
            g.extent.origin_m,
            g.extent.cell_size_m,
            raster.cells,
            raster.origin,
            raster.resolution_m,
        )
        final, worst, rms, yaw = pose_errors(np.asarray(est), truth)
        matched = mapper.slam.counts.matched if mapper.slam is not None else 0
        print(
            f"| {name} | {100 * s.agreement:.1f} % | {100 * s.occupied_precision:.1f} % | "
            f"{100 * s.occupied_recall:.1f} % | {matched} / {len(sim)} | "
            f"{final:.3f} / {worst:.3f} / {rms:.3f} | {yaw:.3f} | "
            f"{1e3 * mapper.times.matching_s / max(mapper.frames, 1):.2f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
