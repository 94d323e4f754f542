"""``floorscan sim``: simulate a robot run in a world and write it as a dataset folder."""

from __future__ import annotations

import argparse
import math
import sys
import time

from ..errors import OptionError
from ..sim import PATTERN_KINDS, Camera, Imaging, Robot, World, simulate_run, write_dataset
from ._output import FOLDER, add_output


def register(sub) -> None:
    p = sub.add_parser(
        "sim",
        help="simulate a run in a world (built-in or file) and write a dataset folder",
        description="Simulates the robot driving the world's tour and writes a dataset folder "
        "(images, odometry, ground truth, rig, calibration scene, simulator truth).",
    )
    p.add_argument(
        "--world",
        default="corridor",
        help=f"built-in world ({', '.join(World.builtin_names())}) or world file (default "
        "%(default)s)",
    )
    p.add_argument(
        "--seconds", type=float, default=60.0, help="simulated robot time [s] (default %(default)s)"
    )
    add_output(p, FOLDER, "dataset folder to write", aliases=("--out",))
    p.add_argument("--seed", type=int, default=0, help="random seed (default %(default)s)")
    p.add_argument("--width", type=int, default=320, help="image width [px] (default %(default)s)")
    p.add_argument(
        "--height", type=int, default=240, help="image height [px] (default %(default)s)"
    )
    p.add_argument(
        "--speed", type=float, default=0.3, help="cruise speed [m/s] (default %(default)s)"
    )
    p.add_argument("--rate", type=float, default=10.0, help="frame rate [Hz] (default %(default)s)")
    p.add_argument(
        "--calibration",
        choices=[*PATTERN_KINDS, "none"],
        default="checkerboard",
        help="calibration scene to render (default %(default)s)",
    )
    p.add_argument("--ideal", action="store_true", help="no sensor noise, blur or vignetting")
    p.add_argument("--no-truth", action="store_true", help="leave out the truth/ folder")
    p.add_argument("--no-labels", action="store_true", help="leave out the per-pixel label images")
    p.add_argument("--threads", type=int, default=2, help="render threads (default %(default)s)")
    p.add_argument(
        "--max-memory-mb",
        type=int,
        default=768,
        help="most memory the rendered frames may take [MB] (default %(default)s; docs/limits.md)",
    )
    p.set_defaults(run=run)


def check_render_memory(args: argparse.Namespace) -> None:
    """The run is rendered in memory (images, and labels unless --no-labels): refuse one that
    would not fit in --max-memory-mb before rendering anything."""
    if not (math.isfinite(args.seconds) and args.seconds >= 0):
        raise OptionError(
            f"invalid option `--seconds`: must be finite and >= 0, got {args.seconds}"
        )
    if not (math.isfinite(args.rate) and args.rate > 0):
        raise OptionError(f"invalid option `--rate`: must be finite and > 0, got {args.rate}")
    frames = math.floor(args.seconds * args.rate + 1e-9) + 1
    layers = 1 if (args.no_labels or args.no_truth) else 2
    mb = frames * max(args.width, 0) * max(args.height, 0) * layers / 2**20
    if mb > args.max_memory_mb:
        raise OptionError(
            f"{frames} frames of {args.width} x {args.height} take {mb:.0f} MB in memory, more "
            f"than --max-memory-mb {args.max_memory_mb}: shorten --seconds, lower the "
            "resolution, add --no-labels, or raise --max-memory-mb"
        )


def run(args: argparse.Namespace) -> int:
    check_render_memory(args)
    world = World.resolve(args.world)
    camera = Camera(
        width=args.width, height=args.height, imaging=Imaging.ideal() if args.ideal else None
    )
    robot = Robot(speed_mps=args.speed, frame_rate_hz=args.rate)
    t0 = time.perf_counter()
    sim = simulate_run(
        world,
        camera=camera,
        robot=robot,
        seconds=args.seconds,
        seed=args.seed,
        labels=not args.no_labels and not args.no_truth,
        truth=not args.no_truth,
        threads=args.threads,
    )
    t1 = time.perf_counter()
    folder = write_dataset(
        sim,
        args.output,
        calibration=None if args.calibration == "none" else args.calibration,
        truth=not args.no_truth,
        labels=not args.no_labels,
        overwrite=args.force,
    )
    t2 = time.perf_counter()
    print(
        f"simulated {len(sim)} frames of {world.name} ({args.seconds:g} s) in {t1 - t0:.1f} s, "
        f"wrote {folder} in {t2 - t1:.1f} s",
        file=sys.stderr,
    )
    return 0
