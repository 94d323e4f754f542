"""``floorscan drive``: the simulated robot follows a world's tour in closed loop with its
camera (or an ideal laser), and the simulator judges contact; ``--suite`` runs the suite."""

from __future__ import annotations

import argparse
import json
import sys

from .._signals import StopRequest
from ..drive import DriveOptions, drive
from ..drive.obstacles import with_obstacles
from ..drive.suite import run_suite
from ..pipeline.config import Config
from ..sim import World
from ._output import FOLDER, add_output

DEFAULT_WORLD = "room"
"""The world driven without --world."""
SECONDS = 600.0
"""Longest drive [s] without --seconds."""
SUITE_SECONDS = 150.0
"""Longest drive of each suite case [s] without --seconds."""


def register(sub) -> None:
    p = sub.add_parser(
        "drive",
        help="drive the simulated robot through a world's tour in closed loop (camera or laser)",
        description="Closed loop in the simulator: camera (ranger + ground table) or ideal laser, "
        "odometry, avoidance map, costmap with inflation and a dynamic-window planner. Writes "
        "summary.json, map.yaml/pgm, path.png and drive.gif into the output folder.",
    )
    p.add_argument(
        "--world",
        action="append",
        default=None,
        help=f"built-in world or world file (default: {DEFAULT_WORLD}; with --suite: "
        "repeatable, the built-in carpet worlds if none)",
    )
    p.add_argument("--speed", type=float, default=0.3, help="top speed [m/s] (default %(default)s)")
    p.add_argument(
        "--seconds",
        type=float,
        default=SECONDS,
        help="longest run [s]; ends when the tour is done (default %(default)s; with --suite "
        f"and no --seconds: {SUITE_SECONDS})",
    )
    p.add_argument("--seed", type=int, default=0, help="noise seed (default %(default)s)")
    p.add_argument(
        "--sensor",
        choices=["camera", "laser"],
        default="camera",
        help="range sensor: the camera or an ideal laser (default %(default)s)",
    )
    p.add_argument(
        "--table",
        choices=["calibrated", "exact"],
        default="calibrated",
        help="ground table: calibrated from the simulated pattern or exact (default %(default)s)",
    )
    p.add_argument(
        "--obstacles", action="store_true", help="place boxes, chairs, tables and bins on the route"
    )
    p.add_argument(
        "--config",
        help="configuration TOML: its [ranger] and [appearance] tables make the range sensor, its [parallax] turns the floor-parallax cue on, its [drive] table gives the avoidance map, the sensor model, the costmap and the planner",
    )
    p.add_argument(
        "--ranger",
        choices=["edge", "appearance", "fused"],
        help=f"range sensor kind (default: {DriveOptions().ranger}, DriveOptions.ranger; a "
        "--config gives the rangers' options, not their kind)",
    )
    p.add_argument("--no-gif", action="store_true", help="leave out drive.gif")
    p.add_argument(
        "--no-scan-matching",
        action="store_true",
        help="drive on odometry alone (default: scans matched against the robot's own map "
        "correct its pose)",
    )
    p.add_argument(
        "--suite",
        action="store_true",
        help="run the suite (carpet worlds x 0.3/0.5/0.8 m/s x seeds, camera and laser)",
    )
    p.add_argument(
        "--seeds", type=int, default=2, help="suite: seeds per case (default %(default)s)"
    )
    add_output(p, FOLDER, "output folder", aliases=("--out",))
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    config = Config.load(args.config) if args.config else None
    ranger = {"ranger": args.ranger} if args.ranger else {}
    # a first SIGINT / SIGTERM / SIGHUP ends the drive after the current frame and the
    # outputs are still written; a second one while writing abandons what is not written yet
    stop = StopRequest()
    if args.suite:
        seconds = args.seconds if args.seconds != SECONDS else SUITE_SECONDS
        kw = {"worlds": args.world} if args.world else {}
        with stop.installed():
            with stop.loop():
                run_suite(
                    args.output,
                    seeds=range(args.seeds),
                    seconds=seconds,
                    table=args.table,
                    scan_matching=not args.no_scan_matching,
                    config=config,
                    stop=stop,
                    **ranger,
                    **kw,
                )
        print(open(f"{args.output}/suite.md").read())
        return 128 + stop.signum if stop.requested else 0
    if args.world and len(args.world) > 1:
        print("error: one --world without --suite", file=sys.stderr)
        return 2
    world = World.resolve(args.world[0] if args.world else DEFAULT_WORLD)
    if args.obstacles:
        world, placed = with_obstacles(world)
        print(f"obstacles: {placed}", file=sys.stderr)
    options = DriveOptions(
        speed_m_s=args.speed,
        seconds=args.seconds,
        seed=args.seed,
        sensor=args.sensor,
        table=args.table,
        keep_frames=0 if args.no_gif else 5,
        scan_matching=not args.no_scan_matching,
        **ranger,
    )
    with stop.installed():
        with stop.loop():
            print(
                f"floorscan drive: {world.name}, up to {options.seconds:g} s "
                "(Ctrl-C stops the drive and still writes its outputs)",
                file=sys.stderr,
                flush=True,
            )
            result = drive(world, options, config=config, stop=stop)
        result.write(args.output, gif=not args.no_gif)
    s = result.summary()
    s.pop("waypoints")
    print(json.dumps(s, indent=1))
    return 128 + stop.signum if stop.requested else 0
