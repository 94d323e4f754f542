"""``floorscan calibrate``: one image of a known floor pattern to a ground lookup table, with an
overlay picture (the paper's Fig. 1c) and an error report."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("calibrate", help="build a ground table from an image of a floor pattern")
    p.add_argument("image", help="calibration image (the robot's camera, pattern on the floor)")
    p.add_argument(
        "--pattern", help="pattern TOML (docs/calibration.md); default: pattern.toml beside IMAGE"
    )
    p.add_argument("-o", "--output", required=True, help="ground table JSON to write")
    p.add_argument("--overlay", help="PNG to write: the pattern as the table sees it, over IMAGE")
    p.add_argument("--report", help="JSON to write: every point's errors, the model, the view")
    p.add_argument("--spacing", type=int, default=8, help="table node spacing [px] (default 8)")
    p.add_argument(
        "--extrapolate",
        action="store_true",
        help="trust the fitted model beyond the pattern (below the horizon, within --max-range)",
    )
    p.add_argument(
        "--margin",
        type=float,
        help="ground beyond the pattern's outline kept without --extrapolate [m] (default: one square / line spacing)",
    )
    p.add_argument(
        "--no-near-field",
        action="store_true",
        help="without --extrapolate, leave out the floor between the camera and the pattern",
    )
    p.add_argument(
        "--max-range", type=float, default=10.0, help="no ground beyond this range [m] (default 10)"
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ..calibration import calibrate, draw_calibration_overlay
    from ..image_io import read_grey, write_png

    image_path = Path(args.image)
    pattern = Path(args.pattern) if args.pattern else image_path.with_name("pattern.toml")
    image = read_grey(image_path)
    table, report = calibrate(
        image,
        pattern,
        spacing_px=args.spacing,
        extrapolate=args.extrapolate,
        margin_m=args.margin,
        near_field=not args.no_near_field,
        max_range_m=args.max_range,
    )
    written = [str(table.save(args.output))]
    if args.overlay:
        written.append(str(write_png(args.overlay, draw_calibration_overlay(image, table, report))))
    if args.report:
        written.append(str(report.save(args.report)))
    print(report.summary())
    for note in report.notes:
        print(f"note: {note}", file=sys.stderr)
    print(f"wrote {', '.join(written)}", file=sys.stderr)
    return 0
