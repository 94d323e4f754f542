"""A box the robot's sensor cannot see, in closed loop: how many contacts before the robot
is past it (issue 15: the bumper's memory, the planner's side of an obstacle the camera
misses).

A 7 x 3 m hall written here (not a world the drive's settings were chosen on), the tour a
straight 5.2 m leg along its middle and back, a box across the leg: sizes 0.3 / 0.45 / 0.6 m, centred
on the leg or 0.2 m to either side. The ideal laser is cut to the hall's walls, so the robot
never sees the box: it learns of it only through its bumper (``AvoidanceMap.mark_bump``,
the loop's back-off). Each setting drives every box and seed; reported: contacts per run
(mean, max), waypoints reached, mean time. The way back passes the box again: a memory
shorter than the way out and back bumps it twice.

    .venv/bin/python bench/drive_bumper.py [--seeds 2]
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace

import numpy as np
from floorscan.drive import DriveOptions, Solids, drive
from floorscan.sim import World

HALL = """
name = "bumper hall"
seed = 5
tour = [[6.0, 1.5], [0.8, 1.5]]
[start]
x = 0.8
y = 1.5
yaw = 0.0
[coverings.carpet]
kind = "carpet"
brightness = 0.35
contrast = 0.06
[[walls]]
from = [0.0, 0.0]
to = [7.0, 0.0]
[[walls]]
from = [7.0, 0.0]
to = [7.0, 3.0]
[[walls]]
from = [7.0, 3.0]
to = [0.0, 3.0]
[[walls]]
from = [0.0, 3.0]
to = [0.0, 0.0]
"""

SETTINGS = {
    "defaults": {},
    "before (5 cm back-off, 30 s memory, 0.12 m face)": {
        "bump_backup_m": 0.05,
        "bump_half_life_s": 30.0,
        "bump_face_half_length_m": 0.12,
    },
    "30 s memory": {"bump_half_life_s": 30.0},
    "5 cm back-off": {"bump_backup_m": 0.05},
    "point mark (0.05 m face)": {"bump_face_half_length_m": 0.05},
    "0.5 m face": {"bump_face_half_length_m": 0.25},
}


def options(seed: int, setting: dict) -> DriveOptions:
    o = DriveOptions(seconds=150, sensor="laser", keep_frames=0, seed=seed)
    map_keys = {k: v for k, v in setting.items() if k.startswith("bump_") and k != "bump_backup_m"}
    o = replace(o, map=replace(o.map, **map_keys))
    if "bump_backup_m" in setting:
        o = replace(o, bump_backup_m=setting["bump_backup_m"])
    return o


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=2)
    args = ap.parse_args()
    walls = Solids.of_world(World.from_toml(HALL))
    laser = Solids.laser
    Solids.laser = lambda self, *a, **k: laser(walls, *a, **k)  # blind to the box
    boxes = [(size, dy) for size in (0.3, 0.45, 0.6) for dy in (-0.2, 0.0, 0.2)]
    rows = []
    for name, setting in SETTINGS.items():
        contacts, reached, times = [], 0, []
        for size, dy in boxes:
            world = World.from_toml(
                HALL
                + f"[[boxes]]\ncenter = [3.2, {1.5 + dy}]\nsize = [{size}, {size}]\n"
                + 'height_m = 0.5\nappearance = "wood"\n'
            )
            for seed in range(args.seeds):
                s = drive(world, options(seed, setting)).summary()
                contacts.append(s["collisions"])
                reached += s["waypoints_reached"]
                times.append(s["duration_s"])
        rows.append(
            {
                "setting": name,
                "runs": len(contacts),
                "contacts_mean": round(float(np.mean(contacts)), 2),
                "contacts_max": int(max(contacts)),
                "reached": reached,
                "time_mean_s": round(float(np.mean(times)), 1),
            }
        )
        print(json.dumps(rows[-1]), flush=True)
    print()
    print("| setting | runs | contacts per run (mean / max) | waypoints reached | mean time [s] |")
    print("| --- | ---: | ---: | ---: | ---: |")
    for r in rows:
        print(
            f"| {r['setting']} | {r['runs']} | {r['contacts_mean']} / {r['contacts_max']} | "
            f"{r['reached']}/{2 * r['runs']} | {r['time_mean_s']} |"
        )


if __name__ == "__main__":
    main()
