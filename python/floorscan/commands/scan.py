"""``floorscan scan``: images or dataset folders in, the public scans CSV out."""

from __future__ import annotations

import argparse
import sys

from ..formats.dataset import image_inputs
from ..formats.image_io import read_grey, read_rgb
from ..pipeline.config import Config
from ..pipeline.mapper import ranger_from_config
from ..ranging.ground_table import GroundTable
from ..ranging.scan import write_scans_csv


def add_ranger_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--table", required=True, help="ground table JSON (from `floorscan calibrate`)")
    p.add_argument(
        "--columns", type=int, default=64, help="number of evenly spaced columns (default 64)"
    )
    p.add_argument(
        "--half-width", type=int, default=4, help="box filter half-width d [px] (default 4)"
    )
    p.add_argument(
        "--threshold", type=float, default=10.0, help="edge threshold, intensity units (default 10)"
    )
    p.add_argument("--refine", choices=["subpixel", "peak", "none"], default="subpixel")
    p.add_argument(
        "--bottom-margin", type=int, default=2, help="rows skipped at the bottom [px] (default 2)"
    )
    p.add_argument(
        "--max-range", type=float, default=3.0, help="farthest range scanned [m] (default 3)"
    )
    p.add_argument(
        "--ranger",
        choices=["edge", "appearance", "fused"],
        default="edge",
        help="range sensor (default edge); appearance and fused read colour and use the "
        "[appearance] table of --config",
    )
    p.add_argument("--config", help="configuration TOML (its [appearance] table)")


def ranger_from_args(args: argparse.Namespace):
    cfg = Config.load(args.config) if getattr(args, "config", None) else Config()
    cfg = cfg.with_overrides(
        {
            "ranger.kind": getattr(args, "ranger", "edge"),
            "ranger.columns": args.columns,
            "ranger.half_width": args.half_width,
            "ranger.threshold": args.threshold,
            "ranger.refine": args.refine,
            "ranger.bottom_margin": args.bottom_margin,
            "ranger.max_range_m": args.max_range,
        }
    )
    return ranger_from_config(GroundTable.load(args.table), cfg)


def register(sub) -> None:
    p = sub.add_parser("scan", help="scan images for the floor boundary, write the scans CSV")
    p.add_argument("inputs", nargs="+", help="image files and/or dataset folders")
    p.add_argument("-o", "--output", required=True, help="scans CSV to write")
    add_ranger_arguments(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    ranger = ranger_from_args(args)
    scans = []
    for t, path in image_inputs(args.inputs):
        image = read_grey(path) if args.ranger == "edge" else read_rgb(path)
        scans.append(ranger.scan(image, timestamp=t))
    write_scans_csv(args.output, scans)
    n = sum(s.count()["boundary"] for s in scans)
    print(f"scanned {len(scans)} image(s), {n} boundary points -> {args.output}", file=sys.stderr)
    return 0
