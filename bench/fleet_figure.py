"""The fleet figure: four recordings of one building (the built-in `lab` world, seeds and start
points not used anywhere else, true poses), each robot with its own calibration, mapped by
`floorscan fleet` on Ray and merged; every map scored against the true occupancy with
floorscan.evaluation.scoring (agreement on the cells both know, known cells).

    .venv/bin/python bench/fleet_figure.py --out bench-out/fleet-figure    # docs/images/fleet-lab.png

True poses: each dataset's odometry.txt is replaced by its groundtruth.txt before mapping, so
the figure measures mapping and merging, not odometry drift.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

FLOORSCAN = [sys.executable, "-m", "floorscan"]
TRINARY = np.array([254, 205, 0], dtype=np.uint8)  # free, unknown, occupied


def simulate(out: Path, world_name: str, seconds: float, starts, seeds) -> list:
    from floorscan.sim import World, simulate_run

    world = World.builtin(world_name)
    points = [tuple(world.start[:2])] + [tuple(p) for p in world.tour]
    recs = []
    for k, (s, seed) in enumerate(zip(starts, seeds)):
        d = out / f"robot-{k + 1}"
        if not (d / "images.txt").is_file():
            (x0, y0), (x1, y1) = points[s], points[(s + 1) % len(points)]
            route = points[s + 1 :] + points[1 : s + 1]
            sim = simulate_run(
                world,
                seconds=seconds,
                seed=seed,
                start=(x0, y0, math.atan2(y1 - y0, x1 - x0)),
                waypoints=np.array(route),
                labels=False,
                threads=2,
            )
            sim.write_dataset(d, overwrite=True)
            shutil.copy(d / "groundtruth.txt", d / "odometry.txt")  # true poses
        table = d / "table.json"
        if not table.is_file():
            subprocess.run(
                FLOORSCAN
                + ["calibrate", str(d / "calibration" / "pattern.png"), "-o", str(table)]
                + ["--extrapolate"],
                check=True,
            )
        recs.append(f"{d}::{table}")
    return recs, world


def classes_of(map_yaml: Path):
    from floorscan import OccupancyGrid

    grid = OccupancyGrid.load(map_yaml)
    e = grid.extent
    return grid.occupancy_classes(), e.origin_m, e.cell_size_m


def on_canvas(classes, origin, cell, canvas_origin, shape) -> np.ndarray:
    out = np.ones(shape, np.uint8)
    dx = int(round((origin[0] - canvas_origin[0]) / cell))
    dy = int(round((origin[1] - canvas_origin[1]) / cell))
    h, w = classes.shape
    ys, xs = slice(max(dy, 0), min(dy + h, shape[0])), slice(max(dx, 0), min(dx + w, shape[1]))
    out[ys, xs] = classes[ys.start - dy : ys.stop - dy, xs.start - dx : xs.stop - dx]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="bench-out/fleet-figure")
    ap.add_argument("--world", default="lab")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--starts", default="0,2,4,6", help="tour points the robots start at")
    ap.add_argument("--seeds", default="31,32,33,34")
    ap.add_argument("--figure", default="docs/images/fleet-lab.png")
    args = ap.parse_args()
    from floorscan.evaluation.demo import side_by_side
    from floorscan.evaluation.scoring import score_map

    out = Path(args.out)
    starts = [int(s) for s in args.starts.split(",")]
    seeds = [int(s) for s in args.seeds.split(",")]
    recs, world = simulate(out / "data", args.world, args.seconds, starts, seeds)
    maps = out / "maps"
    cmd = FLOORSCAN + [
        "fleet",
        *recs,
        "--shared-frame",
        "--ray",
        "local",
        "-o",
        str(maps),
        "--force",
    ]
    print(" ".join(cmd[2:]), file=sys.stderr)
    subprocess.run(cmd, check=True)

    raster = world.occupancy(resolution_m=0.04)
    names = [f"robot-{k + 1}" for k in range(len(recs))] + ["merged"]
    rows, panels = [], []
    for n in names:
        classes, origin, cell = classes_of(maps / n / "map.yaml")
        s = score_map(classes, origin, cell, raster.cells, raster.origin, raster.resolution_m)
        rows.append({"map": n, **s.as_dict()})
        panels.append(
            TRINARY[on_canvas(classes, origin, cell, raster.origin, raster.cells.shape)][::-1]
        )
    truth = np.where(raster.cells < 0, 1, np.where(raster.cells >= 50, 2, 0)).astype(np.uint8)
    panels.append(TRINARY[truth][::-1])
    side_by_side(panels, names + ["truth"], Path(args.figure))
    best_single = max(r["known_cells"] for r in rows[:-1])
    result = {"maps": rows, "merged_over_best_single_known": rows[-1]["known_cells"] / best_single}
    (out / "fleet_figure.json").write_text(json.dumps(result, indent=2))
    print("| map | known cells | agreement | occupied precision | occupied recall |")
    print("|---|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r['map']} | {r['known_cells']} | {100 * r['agreement']:.1f} % | "
            f"{100 * r['occupied_precision']:.1f} % | {100 * r['occupied_recall']:.1f} % |"
        )
    print(f"merged knows {result['merged_over_best_single_known']:.2f}x the best single recording")
    return 0


if __name__ == "__main__":
    sys.exit(main())
