"""``floorscan calibrate``: images of a known floor pattern to a ground lookup table (a physical
camera model with a predicted error per node), with an overlay picture (the paper's Fig. 1c) and
an error report; ``--check TABLE`` scores an existing table on an image instead."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .._atomic import write_atomic
from ..calibration import calibrate, check_table, draw_calibration_overlay
from ..calibration.options import Coverage
from ..errors import OptionError
from ..formats.image_io import read_grey, write_png
from ..pipeline.config import Config
from ..ranging.ground_table import GroundTable
from ._help import config_default
from ._output import FILE, add_output, also_writes


def register(sub) -> None:
    p = sub.add_parser(
        "calibrate",
        help="build a ground table from images of a floor pattern, or --check a table",
    )
    p.add_argument(
        "images",
        nargs="+",
        metavar="IMAGE",
        help="calibration image(s) (the robot's camera, pattern on the floor)",
    )
    p.add_argument(
        "--pattern",
        action="append",
        help="pattern TOML (docs/calibration.md), once or once per image (default: "
        "pattern.toml beside each IMAGE)",
    )
    p.add_argument(
        "--offset",
        type=float,
        action="append",
        metavar="M",
        help="per image: the pattern lay this much further away (+x) than its file says, "
        "e.g. the robot backed up by M metres (default: none, each pattern where its file says)",
    )
    add_output(p, FILE, "ground table JSON to write", required=False)
    p.add_argument(
        "--intrinsics",
        help="known intrinsics: OpenCV FileStorage YAML/XML or ROS "
        "camera_info YAML; only the camera's pose is fitted",
    )
    p.add_argument(
        "--check", metavar="TABLE", help="score TABLE on IMAGE (no fit, no table written)"
    )
    p.add_argument("--overlay", help="PNG to write: the pattern as the table sees it, over IMAGE")
    p.add_argument("--report", help="JSON to write: every point's errors, the model, the view")
    also_writes(p, "overlay")
    also_writes(p, "report")
    p.add_argument(
        "--spacing",
        type=int,
        help=f"table node spacing [px] {config_default('calibration.spacing_px')}",
    )
    p.add_argument(
        "--coverage",
        choices=[c.value for c in Coverage],
        help="nodes with ground: trusted = predicted error within --max-error of the range "
        f"{config_default('calibration.coverage')}; pattern = around the pattern only; "
        "all = wherever the model sees floor",
    )
    p.add_argument(
        "--max-error",
        type=float,
        help="largest predicted error kept, fraction of the range "
        f"{config_default('calibration.max_error_fraction')}",
    )
    p.add_argument("--extrapolate", action="store_true", help="same as --coverage all")
    p.add_argument(
        "--margin",
        type=float,
        help="--coverage pattern: ground kept beyond the points' outline [m] (default: one "
        "square / half a line spacing)",
    )
    p.add_argument(
        "--no-near-field",
        action="store_true",
        help="--coverage pattern: leave out the floor between the camera and the pattern",
    )
    p.add_argument(
        "--max-range",
        type=float,
        help=f"no ground beyond this range [m] {config_default('calibration.max_range_m')}",
    )
    p.add_argument(
        "--config",
        help="configuration TOML: its [calibration] table (flags given here win over it)",
    )
    p.add_argument(
        "--families",
        help="comma-separated lens families to try (default: all; docs/calibration.md)",
    )
    p.set_defaults(run=run)


def calibration_options(args: argparse.Namespace) -> dict:
    """The ``[calibration]`` table of ``--config`` (or its defaults) with the flags given on
    the command line in place of its values."""
    options = (Config.load(args.config) if args.config else Config()).calibration.kwargs()
    flags = {
        "spacing_px": args.spacing,
        "coverage": args.coverage,
        "max_error_fraction": args.max_error,
        "max_range_m": args.max_range,
        "intrinsics": args.intrinsics,
    }
    options.update({k: v for k, v in flags.items() if v is not None})
    return options


def _patterns(args, images):
    if args.pattern:
        return [Path(p) for p in args.pattern]
    return [Path(i).with_name("pattern.toml") for i in images]


def run(args: argparse.Namespace) -> int:
    images = [read_grey(Path(p)) for p in args.images]
    patterns = _patterns(args, args.images)
    if args.check:
        if len(images) != 1:
            raise OptionError("--check scores one image at a time")
        table = GroundTable.load(args.check)
        result = check_table(table, images[0], patterns[0])
        print(result.summary())
        for ring in result.by_range():
            print(
                f"  {ring['near_m']:.1f}-{ring['far_m']:.1f} m: {ring['covered']}/"
                f"{ring['points']} points, RMS {ring['rms_cm']} cm, max {ring['max_cm']} cm"
            )
        if args.report:
            write_atomic(args.report, json.dumps(result.as_dict(), indent=1) + "\n")
            print(f"wrote {args.report}", file=sys.stderr)
        return 0
    if not args.output:
        raise OptionError("give -o TABLE.json (or --check TABLE to score a table)")
    table, report = calibrate(
        images if len(images) > 1 else images[0],
        patterns,
        offsets_m=args.offset,
        extrapolate=args.extrapolate,
        margin_m=args.margin,
        near_field=not args.no_near_field,
        families=args.families.split(",") if args.families else None,
        **calibration_options(args),
    )
    written = [str(table.save(args.output))]
    if args.overlay:
        written.append(
            str(write_png(args.overlay, draw_calibration_overlay(images[0], table, report)))
        )
    if args.report:
        written.append(str(report.save(args.report)))
    print(report.summary())
    for note in report.notes:
        print(f"note: {note}", file=sys.stderr)
    print(f"wrote {', '.join(written)}", file=sys.stderr)
    return 0
