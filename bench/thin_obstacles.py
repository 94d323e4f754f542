"""Recall of chair and table legs within 1 m (issue 13, thin obstacles) against the number of
sampled columns, on the simulator's worlds with legs: the edge ranger at its defaults but
`columns`, exact ground table, 30 s of each world's tour per seed; or, with `--defaults`,
what a new user gets: the configuration's default ranger (fused) and the default calibrated
table (from the simulated checkerboard, as `floorscan eval`).

    .venv/bin/python bench/thin_obstacles.py [--seconds 30] [--seeds 0 1] [--worlds room lab]
        [--columns 64 160 0 spaced] [--obstacle-width-m 0.03] [--at-range-m 1.0] [--defaults]
        [--config CONFIG]

Prints a markdown table: legs in view (sightings), found, recall, per world and column count
(all = every image column).
"""

from __future__ import annotations

import argparse

from floorscan import VisualRanger
from floorscan.evaluation.calibration_error import calibrated_table
from floorscan.evaluation.thin_obstacles import Legs, leg_recall
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import ranger_from_config
from floorscan.sim import World, simulate_run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--worlds", nargs="+", default=None)
    ap.add_argument(
        "--columns",
        nargs="+",
        default=["64", "160", "0", "spaced"],
        help="counts (0 = every column) or `spaced` (columns placed so that no obstacle "
        "--obstacle-width-m wide at --at-range-m falls between two)",
    )
    ap.add_argument("--obstacle-width-m", type=float, default=0.03)
    ap.add_argument("--at-range-m", type=float, default=1.0)
    ap.add_argument("--within", type=float, default=1.0)
    ap.add_argument(
        "--defaults",
        action="store_true",
        help="the configuration's default ranger and calibrated table (not edge, exact)",
    )
    ap.add_argument(
        "--config",
        default=None,
        help="with --defaults: this configuration TOML instead of the defaults "
        "(its ranger and [calibration])",
    )
    args = ap.parse_args()
    if args.config and not args.defaults:
        ap.error("--config needs --defaults (without it: the edge ranger and the exact table)")
    cfg = Config.load(args.config) if args.config else Config()
    worlds = args.worlds or [
        n for n in World.builtin_names() if len(Legs.of_world(World.builtin(n)))
    ]
    print(f"| world | legs | columns | sightings within {args.within:g} m | found | recall |")
    print("|---|---:|---:|---:|---:|---:|")
    totals = {}
    for name in worlds:
        world = World.resolve(name)
        legs = Legs.of_world(world)
        counts = {c: [0, 0] for c in args.columns}
        for seed in args.seeds:
            run = simulate_run(world, seconds=args.seconds, seed=seed, labels=False, threads=2)
            if args.defaults:
                table, _ = calibrated_table(run.camera, calibration=cfg.calibration.kwargs())
            else:
                table = run.camera.ground_table(spacing_px=4, max_range_m=4.0)
            for c in args.columns:
                if c == "spaced":
                    cols = {"obstacle_width_m": args.obstacle_width_m, "range_m": args.at_range_m}
                else:
                    cols = int(c) or run.camera.width
                if args.defaults:
                    ranger = ranger_from_config(table, cfg, columns=cols)
                else:
                    ranger = VisualRanger(table, columns=cols)
                scans = [ranger.scan(im, timestamp=0.1 * k) for k, im in enumerate(run.images)]
                r = leg_recall(legs, run.truth, scans, within_m=args.within)
                counts[c][0] += r.seen
                counts[c][1] += r.found
        for c in args.columns:
            seen, found = counts[c]
            t = totals.setdefault(c, [0, 0])
            t[0] += seen
            t[1] += found
            label = {"0": "all"}.get(c, c)
            rec = f"{100 * found / seen:.1f} %" if seen else "-"
            print(f"| {name} | {len(legs)} | {label} | {seen} | {found} | {rec} |")
    for c, (seen, found) in totals.items():
        label = {"0": "all"}.get(c, c)
        rec = f"{100 * found / seen:.1f} %" if seen else "-"
        print(f"| **all worlds** | | {label} | {seen} | {found} | **{rec}** |")


if __name__ == "__main__":
    main()
