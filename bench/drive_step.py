"""Closed-loop step time (ranging + scan matching + avoidance map + costmap + dynamic window;
the plan's navigation function separately, it runs every fifth frame) per frame, at a
resolution.

    .venv/bin/python bench/drive_step.py --width 640 --height 480 --seconds 10 [--ranger KIND]
    .venv/bin/python bench/drive_step.py --stages --width 640 --height 480 [--ranger KIND]
        [--no-band]

``--ranger``: the range sensor (edge, appearance, fused; default edge, the figures before the
fused ranger became the configuration's default; ``floorscan drive`` uses the configuration's).
"""

from __future__ import annotations

import argparse
import json

from floorscan.drive import DriveOptions, drive
from floorscan.pipeline.config import Config
from floorscan.sim import Camera, World


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--sensor", default="camera")
    ap.add_argument("--stages", action="store_true", help="time each stage on a fixed frame")
    ap.add_argument("--ranger", default="edge", choices=["edge", "appearance", "fused"])
    ap.add_argument(
        "--no-band", action="store_true", help="without the drive's contrast band (mid_range_m)"
    )
    a = ap.parse_args()
    cfg = Config().with_overrides({"ranger.kind": a.ranger})
    if a.stages:
        print(
            json.dumps(
                {
                    "resolution": f"{a.width}x{a.height}",
                    "ranger": a.ranger,
                    "band": not a.no_band,
                    **stages(a.width, a.height, config=cfg, band=not a.no_band),
                }
            )
        )
        return
    cam = Camera(width=a.width, height=a.height)
    r = drive(
        World.builtin("corridor"),
        DriveOptions(
            seconds=a.seconds, table="exact", sensor=a.sensor, keep_frames=0, columns=a.width // 2
        ),
        camera=cam,
        config=cfg,
    )
    s = r.summary()
    print(
        json.dumps(
            {
                "resolution": f"{a.width}x{a.height}",
                "ranger": a.ranger,
                "frames": len(r.record.step_s),
                "step_ms_median": s["step_ms_median"],
                "plan_ms_median": s["plan_ms_median"],
            }
        )
    )


def corridor_frame(width: int = 640, height: int = 480, config=None, band: bool = True):
    """The fixed frame the stage timings use: (camera, exact table, the drive's ranger (its
    contrast band included) on every second column, the corridor's start pose, its rendered
    image)."""
    from floorscan.drive import make_table
    from floorscan.drive.loop import drive_ranger
    from floorscan.sim import render_image

    world, cam = World.builtin("corridor"), Camera(width=width, height=height)
    table = make_table(cam, "exact")
    config = config or Config()
    options = DriveOptions(columns=width // 2, ranger=config.ranger.kind)
    if not band:
        options = DriveOptions(columns=width // 2, ranger=config.ranger.kind, mid_range_m=None)
    ranger = drive_ranger(table, options, config)
    pose = tuple(world.start)
    return cam, table, ranger, pose, render_image(world, cam, pose)


def stages(
    width: int = 640, height: int = 480, repeats: int = 50, config=None, band: bool = True
) -> dict:
    """Median time [ms] of each stage of one closed-loop step on a fixed corridor frame."""
    import time

    import numpy as np
    from floorscan.drive import (
        AvoidanceMap,
        CostmapOptions,
        DwaOptions,
        choose_velocity,
        inflate,
        navigation_function,
    )
    from floorscan.mapping.scan_matcher import ScanMatcher
    from floorscan.mapping.scan_matcher import boundary_points_robot as _visual_points

    cam, table, ranger, pose, image = corridor_frame(width, height, config, band)
    m = AvoidanceMap(center=pose[:2])
    co, dwa = CostmapOptions(), DwaOptions()
    out: dict = {"ranging": [], "match": [], "map": [], "costmap": [], "dwa": [], "plan": []}
    nav = None
    matcher = ScanMatcher(center=pose[:2])
    matcher.correct(_visual_points(ranger.scan(image), cam.robot_from_camera), pose)
    for k in range(repeats):
        t0 = time.perf_counter()
        scan = ranger.scan(image)
        tm = time.perf_counter()
        # a prior 5 cm and 0.02 rad off, alternating (the field is cached as in a drive)
        off = 0.05 if k % 2 else -0.05
        prior = (pose[0] + off, pose[1] - off, pose[2] + 0.4 * off)
        matcher.correct(_visual_points(scan, cam.robot_from_camera), prior)
        t1 = time.perf_counter()
        m.decay(0.1)
        m.insert_visual(scan, pose, mount=cam.robot_from_camera, table=table)
        t2 = time.perf_counter()
        cost = inflate(m.occupied(), m.cell, co)
        t3 = time.perf_counter()
        nav = navigation_function(cost, m.cell, m.origin_m, (3.95, 0.0), co, known=m.known())
        t4 = time.perf_counter()
        choose_velocity(pose, (0.3, 0.0), cost, m.origin_m, m.cell, nav, (3.95, 0.0), 0.1, dwa)
        t5 = time.perf_counter()
        for k, dt in zip(
            ("ranging", "match", "map", "costmap", "plan", "dwa"),
            (tm - t0, t1 - tm, t2 - t1, t3 - t2, t4 - t3, t5 - t4),
        ):
            out[k].append(1e3 * dt)
    return {k: round(float(np.median(v)), 3) for k, v in out.items()}


if __name__ == "__main__":
    main()
