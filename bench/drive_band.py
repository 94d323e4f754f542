"""The drive with and without the edge ranger's contrast band (`DriveOptions.mid_range_m`),
camera robot, beside the laser robot (EVALUATION.md, "A face the colour of the floor").

    .venv/bin/python bench/drive_band.py --world bench/worlds/study.toml [--speeds 0.3 0.5]
        [--seeds 2] [--seconds 300]
"""

from __future__ import annotations

import argparse
import json

from floorscan.drive import DriveOptions, drive
from floorscan.drive.obstacles import with_obstacles
from floorscan.sim import World

KEYS = (
    "collisions",
    "waypoints_reached",
    "waypoints_total",
    "waypoints_reached_true",
    "duration_s",
    "pose_error_m_max",
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--world", required=True)
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.3, 0.5])
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--seconds", type=float, default=300.0)
    a = ap.parse_args()
    world, _ = with_obstacles(World.resolve(a.world))
    band = DriveOptions().mid_range_m
    for speed in a.speeds:
        for seed in range(a.seeds):
            for mid in (band, None):
                o = DriveOptions(
                    speed_m_s=speed,
                    seed=seed,
                    table="exact",
                    keep_frames=0,
                    seconds=a.seconds,
                    mid_range_m=mid,
                )
                s = drive(world, o).summary()
                contacts = [
                    (c["time_s"], round(c["x"], 2), round(c["y"], 2)) for c in s["contacts"]
                ]
                row = {"speed": speed, "seed": seed, "band": mid, **{k: s[k] for k in KEYS}}
                print(json.dumps({**row, "contacts": contacts}), flush=True)
        o = DriveOptions(speed_m_s=speed, seed=0, sensor="laser", keep_frames=0, seconds=a.seconds)
        s = drive(world, o).summary()
        print(json.dumps({"speed": speed, "seed": 0, "sensor": "laser", **{k: s[k] for k in KEYS}}))


if __name__ == "__main__":
    main()
