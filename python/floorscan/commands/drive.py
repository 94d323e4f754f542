"""``floorscan drive``: the simulated robot follows a world's tour in closed loop with its
camera (or an ideal laser), and the simulator judges contact; ``--suite`` runs the suite."""

from __future__ import annotations

import argparse
import json
import sys

from .._signals import StopRequest
from ..drive import SENSORS, TABLES, DriveOptions, drive
from ..drive.obstacles import with_obstacles
from ..drive.suite import run_suite
from ..options import choices, defaults
from ..pipeline.config import Config
from ..sim import World
from ._output import FOLDER, add_output

DEFAULT_WORLD = "room"
"""The world driven without --world."""
RUN = defaults("drive_run")
"""The drive's own settings' defaults (the core's ``DriveRunOptions``; a config's
``[drive.run]`` sets them for a file, the flags for one command)."""
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
    # flags given override the config's [drive.run], which overrides the core's defaults
    p.add_argument(
        "--speed",
        type=float,
        help=f"top speed [m/s] (default {RUN['speed_m_s']:g}, the config's drive.run.speed_m_s)",
    )
    p.add_argument(
        "--seconds",
        type=float,
        help="longest run [s]; ends when the tour is done (default "
        f"{RUN['seconds']:g}, the config's drive.run.seconds); with --suite and no --seconds: "
        f"{SUITE_SECONDS:g}",
    )
    p.add_argument(
        "--seed", type=int, help=f"noise seed (default {RUN['seed']}, the config's drive.run.seed)"
    )
    p.add_argument(
        "--sensor",
        choices=SENSORS,
        help="range sensor: the camera or an ideal laser (default "
        f"{RUN['sensor']}, the config's drive.run.sensor)",
    )
    p.add_argument(
        "--table",
        choices=TABLES,
        help="ground table: calibrated from the simulated pattern or exact (default "
        f"{RUN['table']}, the config's drive.run.table)",
    )
    p.add_argument(
        "--obstacles", action="store_true", help="place boxes, chairs, tables and bins on the route"
    )
    p.add_argument(
        "--config",
        help="configuration TOML: its [ranger] and [appearance] tables make the range sensor, its [parallax] turns the floor-parallax cue on, its [drive] table gives the avoidance map, the sensor model, the costmap, the planner and the drive's own settings ([drive.run])",
    )
    p.add_argument(
        "--ranger",
        choices=choices("drive_run", "ranger"),
        help=f"range sensor kind (default {RUN['ranger']}, the config's drive.run.ranger); a "
        "--config's [ranger] gives the rangers' options, not their kind",
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


def settings(args: argparse.Namespace, config) -> dict:
    """The drive's own settings: the flags given, over the config's ``[drive.run]``, over the
    core's defaults."""
    own = dict(config.drive.options()["run"]) if config is not None else dict(RUN)
    flags = {
        "speed_m_s": args.speed,
        "seconds": args.seconds,
        "seed": args.seed,
        "sensor": args.sensor,
        "table": args.table,
        "ranger": args.ranger,
    }
    own.update({k: v for k, v in flags.items() if v is not None})
    if args.no_gif:
        own["keep_frames"] = 0
    if args.no_scan_matching:
        own["scan_matching"] = False
    if own["mid_range_m"] is not None:
        own["mid_range_m"] = tuple(own["mid_range_m"])
    return own


def run(args: argparse.Namespace) -> int:
    config = Config.load(args.config) if args.config else None
    own = settings(args, config)
    ranger = {"ranger": own["ranger"]}
    # a first SIGINT / SIGTERM / SIGHUP ends the drive after the current frame and the
    # outputs are still written; a second one while writing abandons what is not written yet
    stop = StopRequest()
    if args.suite:
        seconds = args.seconds if args.seconds is not None else SUITE_SECONDS
        kw = {"worlds": args.world} if args.world else {}
        with stop.installed():
            with stop.loop():
                run_suite(
                    args.output,
                    seeds=range(args.seeds),
                    seconds=seconds,
                    table=own["table"],
                    scan_matching=own["scan_matching"],
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
    options = DriveOptions(**own)
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
