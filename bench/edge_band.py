"""Where a lower contrast floor finds boundaries and where it invents them, by ground range
(the evidence for the edge ranger's `mid_range_m` band; docs/visual-range-sensor.md).

The ideal-laser robot drives a world's tour (with obstacles placed on it) so the poses do not
depend on the camera; every tenth frame is rendered and scanned by the edge ranger (160
columns, exact table) at `contrast` 0.12 (the default) and 0.06. Per range bin of the reading:
boundaries found within 4 rows of the truth's, and false ones (a boundary nearer than the
truth's, or where the truth has none).

    .venv/bin/python bench/edge_band.py [--worlds corridor room ...] [--seconds 100]
"""

from __future__ import annotations

import argparse

import numpy as np
from floorscan.drive import DriveOptions, drive, make_table
from floorscan.drive.obstacles import with_obstacles
from floorscan.ranging.ranger import VisualRanger
from floorscan.sim import Camera, World, render

BINS = [0.0, 0.6, 1.2, 2.0, 3.1]
CONTRASTS = (0.12, 0.06)


def measure(name: str, seconds: float):
    world, _ = with_obstacles(World.resolve(name))
    o = DriveOptions(sensor="laser", seed=0, keep_frames=0, seconds=seconds)
    poses = np.asarray(drive(world, o).record.poses)
    camera = Camera()
    table = make_table(camera, "exact")
    rangers = {c: VisualRanger(table, columns=160, contrast=c) for c in CONTRASTS}
    found = {c: np.zeros(len(BINS) - 1) for c in CONTRASTS}
    false = {c: np.zeros(len(BINS) - 1) for c in CONTRASTS}
    for i in range(0, len(poses), 10):
        image, truth = render(world, camera, tuple(poses[i]), frame=i)
        for c, ranger in rangers.items():
            scan = ranger.scan(image)
            cols = np.asarray(scan.columns).astype(int)
            status, rows = np.asarray(scan.status_codes), np.asarray(scan.rows)
            b = np.digitize(np.hypot(np.asarray(scan.x), np.asarray(scan.y)), BINS) - 1
            t_status, t_rows = truth.status[cols], truth.rows[cols]
            ok = (status == 0) & (t_status == 0) & (np.abs(rows - t_rows) <= 4)
            bad = (status == 0) & ~((t_status == 0) & (rows <= t_rows + 4))
            for j in range(len(BINS) - 1):
                found[c][j] += (ok & (b == j)).sum()
                false[c][j] += (bad & (b == j)).sum()
    return found, false


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--worlds",
        nargs="+",
        default=["corridor", "room", "bench/worlds/office_l.toml", "bench/worlds/open_plan.toml"],
    )
    ap.add_argument("--seconds", type=float, default=100.0)
    args = ap.parse_args()
    bins = [f"{a:g}-{b:g} m" for a, b in zip(BINS[:-1], BINS[1:])]
    print("| world | contrast | " + " | ".join(f"found / false, {b}" for b in bins) + " |")
    print("| --- | --- |" + " --- |" * len(bins))
    for name in args.worlds:
        found, false = measure(name, args.seconds)
        for c in CONTRASTS:
            cells = " | ".join(f"{int(f)} / {int(x)}" for f, x in zip(found[c], false[c]))
            print(f"| {name} | {c} | {cells} |", flush=True)


if __name__ == "__main__":
    main()
