"""``floorscan scan``: images or dataset folders in, the public scans CSV out."""

from __future__ import annotations

import argparse
import sys

from ..dataset import image_inputs
from ..ground_table import GroundTable
from ..image_io import read_grey
from ..ranger import VisualRanger
from ..scan import write_scans_csv


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


def ranger_from_args(args: argparse.Namespace) -> VisualRanger:
    return VisualRanger(
        GroundTable.load(args.table),
        columns=args.columns,
        half_width=args.half_width,
        threshold=args.threshold,
        refine=args.refine,
        bottom_margin=args.bottom_margin,
        max_range_m=args.max_range,
    )


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
        scans.append(ranger.scan(read_grey(path), timestamp=t))
    write_scans_csv(args.output, scans)
    n = sum(s.count()["boundary"] for s in scans)
    print(f"scanned {len(scans)} image(s), {n} boundary points -> {args.output}", file=sys.stderr)
    return 0
