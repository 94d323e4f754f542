"""``floorscan demo``: the main job on built-in data, with no files needed."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from ..ground_table import GroundTable
from ..image_io import write_png
from ..lens import CameraMount, Lens
from ..overlay import draw_scan_overlay
from ..ranger import VisualRanger


def register(sub) -> None:
    p = sub.add_parser("demo", help="run the pipeline on built-in data and write pictures")
    p.add_argument("-o", "--output", default="demo-out", help="output folder (default demo-out)")
    p.set_defaults(run=run)


def synthetic_frame(table: GroundTable, wall_x_m: float = 1.6, seed: int = 0) -> np.ndarray:
    """A carpet (low-contrast noise) with a wall at x = wall_x_m, seen through the table."""
    rng = np.random.default_rng(seed)
    h, w = table.image_height, table.image_width
    v, u = np.mgrid[0:h, 0:w].astype(np.float64)
    x, _ = table.lookup(u, v)
    floor = np.isfinite(x) & (x < wall_x_m)
    image = np.where(floor, 95.0, 185.0) + rng.normal(0, 3.0, size=(h, w))
    return np.clip(np.rint(image), 0, 255).astype(np.uint8)


def run(args: argparse.Namespace) -> int:
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    lens = Lens.kannala_brandt(fx=160, fy=160, cx=319.5, cy=239.5, k1=-0.02, k2=0.003)
    table = GroundTable.from_camera(
        lens, CameraMount(height_m=0.45, tilt_rad=0.55), image_width=640, image_height=480
    )
    image = synthetic_frame(table)
    ranger = VisualRanger(table, columns=48)
    scan = ranger.scan(image)
    overlay = out / "overlay.png"
    write_png(overlay, draw_scan_overlay(image, scan))
    table.save(out / "table.json")
    print(f"demo: {scan.count()}", file=sys.stderr)
    print(f"wrote {overlay} and {out / 'table.json'}")
    return 0
