"""``floorscan scan``: images or dataset folders in, the public scans CSV out."""

from __future__ import annotations

import argparse
import sys

from ..formats.dataset import image_inputs
from ..formats.image_io import read_grey, read_rgb
from ..pipeline.config import Config, default_value
from ..pipeline.mapper import RANGER_KINDS, ranger_from_config
from ..ranging.ground_table import GroundTable
from ..ranging.ranger import VisualRanger
from ..ranging.scan import write_scans_csv
from ._help import config_default
from ._output import FILE, add_output


def add_ranger_arguments(p: argparse.ArgumentParser) -> None:
    """Flags of the ``[ranger]`` options; unset flags leave the config file's (or the Rust
    default) value. ``--half-width`` and ``--refine`` are the older spellings."""

    def default(key: str) -> str:
        return config_default("ranger." + key)

    columns = default_value("ranger.columns")
    p.add_argument("--table", required=True, help="ground table JSON (from `floorscan calibrate`)")
    p.add_argument(
        "--columns",
        type=int,
        help="number of evenly spaced columns (default: placed so that no obstacle "
        f"{columns['obstacle_width_m']} m wide at {columns['range_m']} m stands between two, "
        "the config's ranger.columns)",
    )
    p.add_argument(
        "--half-width-px",
        "--half-width",
        dest="half_width_px",
        type=int,
        help=f"box filter half-width d [px] {default('half_width_px')}",
    )
    p.add_argument(
        "--threshold",
        type=float,
        help="least edge threshold, intensity units (each frame's noise and the floor's "
        f"brightness raise it: ranger.noise_multiple, ranger.contrast) {default('threshold')}",
    )
    p.add_argument(
        "--refinement",
        "--refine",
        dest="refinement",
        help="boundary placement: step | sub_pixel | peak | first_crossing (the paper's) "
        f"{default('refinement')}",
    )
    p.add_argument(
        "--bottom-margin",
        type=int,
        help=f"rows skipped at the bottom [px] {default('start.bottom_margin')}",
    )
    p.add_argument(
        "--max-range",
        type=float,
        help=f"farthest range scanned [m], inf: no limit {default('max_range_m')}",
    )
    p.add_argument(
        "--ranger",
        choices=RANGER_KINDS,
        help=f"range sensor {default('kind')}; appearance and fused read colour and use the "
        "[appearance] table of --config",
    )
    p.add_argument("--config", help="configuration TOML (its [ranger] and [appearance] tables)")


def config_from_args(args: argparse.Namespace) -> Config:
    """The configuration of ``--config`` (or the defaults) with the ranger flags applied."""
    cfg = Config.load(args.config) if getattr(args, "config", None) else Config()
    refine = args.refinement
    return cfg.with_overrides(
        {
            "ranger.kind": getattr(args, "ranger", None),
            "ranger.columns": args.columns,
            "ranger.half_width_px": args.half_width_px,
            "ranger.threshold": args.threshold,
            "ranger.refine": refine,  # either spelling (LEGACY_KEYS translates the old one)
            "ranger.bottom_margin": args.bottom_margin,
            "ranger.max_range_m": args.max_range,
        }
    )


def ranger_from_args(args: argparse.Namespace):
    return ranger_from_config(GroundTable.load(args.table), config_from_args(args))


def register(sub) -> None:
    p = sub.add_parser("scan", help="scan images for the floor boundary, write the scans CSV")
    p.add_argument("inputs", nargs="+", help="image files and/or dataset folders")
    add_output(p, FILE, "scans CSV to write")
    add_ranger_arguments(p)
    p.add_argument(
        "--lenient",
        action="store_true",
        help="range a truncated image as far as it decodes, with a warning (default: an error)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    ranger = ranger_from_args(args)
    scans = []
    for t, path in image_inputs(args.inputs):
        if isinstance(ranger, VisualRanger):
            image = read_grey(path, lenient=args.lenient)
        else:
            image = read_rgb(path)
        scans.append(ranger.scan(image, timestamp=t))
    write_scans_csv(args.output, scans)
    n = sum(s.count()["boundary"] for s in scans)
    print(f"scanned {len(scans)} image(s), {n} boundary points -> {args.output}", file=sys.stderr)
    return 0
