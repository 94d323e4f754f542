"""``floorscan demo``: the main job on the built-in simulated office, with no files needed."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..evaluation.demo import run_demo
from ..sim import World
from ._output import FOLDER, add_output


def register(sub) -> None:
    p = sub.add_parser(
        "demo", help="simulate the office corridor, calibrate, map, score; write pictures"
    )
    add_output(p, FOLDER, "output folder", default="demo-out")
    p.add_argument(
        "--world",
        default="corridor",
        help=f"built-in world ({', '.join(World.builtin_names())}) (default %(default)s)",
    )
    p.add_argument(
        "--seconds", type=float, default=60.0, help="simulated seconds (default %(default)s)"
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default %(default)s)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    out = Path(args.output)
    s = run_demo(out, world_name=args.world, seconds=args.seconds, seed=args.seed)
    b, m, p = s["boundary"], s["map_agreement"], s["performance"]
    print(
        f"demo: {s['frames']} frames of the simulated {s['world']} in {s['wall_s']['total']:.1f} s"
    )
    print(
        f"  boundary points more than 10 cm from the true obstacle: {100 * b['far_point_share']:.1f} %  (column error rate {100 * b['error_rate']:.1f} %)"
    )
    print(
        f"  map agreement with the true occupancy: {100 * m['true_poses']['agreement']:.1f} % (true poses), {100 * m['odometry']['agreement']:.1f} % (odometry)"
    )
    print(
        f"  ranging {p['ms_per_frame']:.3f} ms/frame, mapping {p['ms_per_point'] * 1e3:.2f} us/point"
    )
    print((out / "performance.md").read_text(), end="")
    print(
        f"outputs in {out}/: maps_side_by_side.png, run/ (map.yaml, map.png, scans.csv, bag/, overlay.gif, local/), calibration/, dataset/, demo_summary.json"
    )
    return 0
