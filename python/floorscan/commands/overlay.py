"""``floorscan overlay``: an image with each column's result drawn on it (paper Fig. 1b)."""

from __future__ import annotations

import argparse
import sys

from ..formats.image_io import read_grey, write_png
from ..ranging.overlay import draw_scan_overlay
from ._output import FILE, add_output
from .scan import add_ranger_arguments, ranger_from_args


def register(sub) -> None:
    p = sub.add_parser("overlay", help="draw the found boundary points on an image")
    p.add_argument("image", help="image file")
    add_output(p, FILE, "PNG to write")
    add_ranger_arguments(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    ranger = ranger_from_args(args)
    image = read_grey(args.image)
    scan = ranger.scan(image)
    write_png(args.output, draw_scan_overlay(image, scan))
    print(f"{scan.count()} -> {args.output}", file=sys.stderr)
    return 0
