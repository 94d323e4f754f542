"""``floorscan map-log``: a CARMEN laser log in, a ROS map_server map (and a picture) out."""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import List

import numpy as np

from ..errors import DatasetError
from ..formats.carmen import LaserReading, read_carmen
from ..formats.carmen_odometry import log_odometry
from ..formats.trajectory import Trajectory, compose, inverse, write_tum
from ..mapping import pose_graph
from ..mapping.grid import OccupancyGrid
from ..pipeline.config import Config
from ..pipeline.laser_odometry import lasers_at_odometry
from ..pipeline.mapper import grid_kwargs
from ._help import config_default
from ._output import FILE, add_output, also_writes, refuse_existing


def register(sub) -> None:
    p = sub.add_parser(
        "map-log",
        help="build an occupancy map from a CARMEN laser log (FLASER / ROBOTLASER1), "
        "write map_server YAML + PGM",
    )
    p.add_argument("log", help="CARMEN log file (plain or .gz)")
    add_output(p, FILE, "map YAML to write (the PGM goes beside it)")
    p.add_argument(
        "--png", default=None, help="also write a picture of the map (paper look) to this PNG"
    )
    also_writes(p, "png")
    p.add_argument(
        "--png-scale", type=int, default=1, help="pixels per cell in the PNG (default %(default)s)"
    )
    p.add_argument(
        "--cell-size",
        type=float,
        help=f"cell size [m] {config_default('grid.cell_size_m')}",
    )
    p.add_argument(
        "--max-range",
        type=float,
        default=40.0,
        help="ranges at or beyond this [m] are 'no return': they clear up to it and mark "
        "nothing (default %(default)s)",
    )
    p.add_argument(
        "--no-return",
        choices=["ignore", "clear"],
        default="ignore",
        help="what a no-return reading does: 'ignore' (in real buildings most come from glass "
        "and open doors, and clearing them paints the outdoors free) or 'clear' (free space up "
        "to --max-range) (default %(default)s)",
    )
    p.add_argument(
        "--min-range",
        type=float,
        default=0.05,
        help="shorter ranges are ignored [m] (default %(default)s)",
    )
    p.add_argument(
        "--hit",
        type=float,
        help="log-odds added to a cell seen occupied [nats] "
        + config_default("sensors.laser.hit_nats"),
    )
    p.add_argument(
        "--miss",
        type=float,
        help="log-odds added to a cell seen free [nats] "
        + config_default("sensors.laser.miss_nats"),
    )
    p.add_argument(
        "--mode",
        choices=["trinary", "scale"],
        default="trinary",
        help="map_server image mode (default %(default)s)",
    )
    p.add_argument(
        "--max-cells",
        type=int,
        help="most cells the map may span; a pose farther out is an error "
        + config_default("grid.max_cells"),
    )
    p.add_argument(
        "--ray-walk",
        metavar="WALK",
        help="which cells a beam clears: exact (every cell it crosses, as OctoMap) or thin (one "
        "per step along its major axis, as costmap_2d and Bonxai: faster) "
        + config_default("grid.ray_walk"),
    )
    p.add_argument(
        "--lenient",
        action="store_true",
        help="skip malformed lines (reported with their line numbers) instead of failing",
    )
    p.add_argument(
        "--poses",
        choices=["log", "odometry"],
        default="log",
        help="where each scan is inserted: 'log' (the pose its line carries: a corrected log's "
        "SLAM poses, a raw log's odometry) or 'odometry' (the robot's raw odometry, rebuilt from "
        "a corrected log's ODOM lines, then corrected as --slam says: docs/slam.md) "
        "(default %(default)s)",
    )
    p.add_argument(
        "--slam",
        choices=["graph", "local", "off"],
        default="graph",
        help="with --poses odometry: 'graph' (scans matched against a rolling submap, loop "
        "closures, a pose graph optimised by GTSAM: pip install 'floorscan[slam]'; local "
        "matching, with a warning, where GTSAM is not installed), 'local' (each scan matched "
        "against those before it, the camera runs' [slam] local mode) or 'off' (dead "
        "reckoning); the config's [slam.graph] and [slam.matcher] tune them "
        "(default %(default)s)",
    )
    p.add_argument(
        "--trajectory",
        metavar="TUM",
        help="also write the robot's pose at each scan as the map placed it (TUM format); with "
        "--poses odometry, the raw odometry beside it as <name>_odometry.tum",
    )
    also_writes(p, "trajectory")
    p.add_argument(
        "--config",
        help="configuration TOML (its [grid], [sensors.laser] and, with --poses odometry, "
        "[slam.graph] and [slam.matcher] tables)",
    )
    p.set_defaults(run=run)


def layout_groups(lasers: List[LaserReading]) -> List[List[LaserReading]]:
    """Runs of consecutive scans sharing a beam layout (one batch insert each)."""
    groups: List[List[LaserReading]] = []
    for r in lasers:
        key = (r.ranges.size, r.angle_min, r.angle_increment)
        if (
            groups
            and (groups[-1][0].ranges.size, groups[-1][0].angle_min, groups[-1][0].angle_increment)
            == key
        ):
            groups[-1].append(r)
        else:
            groups.append([r])
    return groups


def map_lasers(
    grid: OccupancyGrid,
    lasers: List[LaserReading],
    *,
    max_range_m: float,
    min_range_m: float,
    clear_no_return: bool = False,
):
    """Inserts every scan at its laser pose; returns (rays, cells traversed, seconds). Ranges
    at or beyond the smaller of ``max_range_m`` and the log's stated maximum are no return:
    they clear up to it if ``clear_no_return``, else they are ignored."""
    rays = cells = 0
    seconds = 0.0
    for group in layout_groups(lasers):
        ranges = np.stack([r.ranges for r in group])
        poses = np.array([r.laser_pose for r in group], dtype=np.float64)
        stated = [r.max_range for r in group if r.max_range is not None]
        range_max = min([max_range_m] + stated)
        if not clear_no_return:
            ranges[ranges >= range_max] = -np.inf  # REP 117 "too close": ignored
        t0 = time.perf_counter()
        stats = grid.insert_lasers(
            ranges,
            poses=poses,
            angle_min=group[0].angle_min,
            angle_increment=group[0].angle_increment,
            range_min_m=min_range_m,
            range_max_m=range_max,
        )
        seconds += time.perf_counter() - t0
        rays += stats.rays
        cells += stats.cells_traversed
    return rays, cells, seconds


def robot_trajectory(logged: List[LaserReading], placed: List[LaserReading]) -> Trajectory:
    """The robot's pose at each scan where ``placed`` put its laser (``logged``: the same
    readings as read, whose robot and laser poses give the laser's mount)."""
    rows = []
    for r, q in zip(logged, placed):
        mount = compose(inverse(r.robot_pose), r.laser_pose)
        rows.append((r.timestamp, *compose(q.laser_pose, inverse(mount))))
    return Trajectory.from_increasing(rows)


def odometry_path(path) -> Path:
    """``x.tum`` -> ``x_odometry.tum``."""
    p = Path(path)
    return p.with_name(p.stem + "_odometry" + (p.suffix or ".tum"))


def _describe(summary) -> str:
    text = f"odometry {summary['odometry']}"
    if summary["slam"] == "graph":
        text += (
            f"; pose graph: {summary['keyframes']} keyframes, {summary['loop_closures']} loop "
            f"closures, {summary['frames_matched']} of "
            f"{summary['frames_matched'] + summary['frames_not_matched']} scans matched to the "
            f"submap, final correction {summary['final_correction_m']:.2f} m / "
            f"{math.degrees(summary['final_correction_rad']):.1f} deg"
        )
    elif summary["slam"] == "local":
        text += (
            f"; scan matching: {summary['frames_matched']} of "
            f"{summary['frames_matched'] + summary['frames_not_matched']} scans matched, "
            f"final correction {summary['final_correction_m']:.2f} m / "
            f"{math.degrees(summary['final_correction_rad']):.1f} deg"
        )
    else:
        text += "; no scan matching ([slam] mode off)"
    return text


def peak_rss_mb() -> float:
    """Peak resident memory of this process [MB] (Linux reports KiB)."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run(args: argparse.Namespace) -> int:
    refuse_existing([(Path(args.output).with_suffix(".pgm"), FILE)], force=args.force)
    log = read_carmen(args.log, strict=not args.lenient)
    for lineno, message in log.bad_lines:
        print(f"floorscan map-log: skipped bad line {lineno}: {message}", file=sys.stderr)
    if not log.lasers:
        raise DatasetError(f"{args.log}: no FLASER or ROBOTLASER1 lines")
    cfg = Config.load(args.config) if args.config else Config()
    cfg = cfg.with_overrides(
        {
            "grid.cell_size_m": args.cell_size,
            "sensors.laser.hit_nats": args.hit,
            "sensors.laser.miss_nats": args.miss,
            "grid.max_cells": args.max_cells,
            "grid.ray_walk": args.ray_walk,
        }
    )
    grid = OccupancyGrid(**grid_kwargs(cfg))
    lasers = log.lasers
    if args.poses == "odometry":
        slam = args.slam
        if slam == "graph" and not pose_graph.AVAILABLE:
            print(
                "floorscan map-log: warning: no loop closure (GTSAM is not installed: "
                f"{pose_graph.INSTALL_HINT}); local scan matching instead",
                file=sys.stderr,
            )
            slam = "local"
        cfg = cfg.with_overrides({"slam.mode": slam})
        lasers, summary = lasers_at_odometry(
            log, cfg, range_max_m=args.max_range, range_min_m=args.min_range
        )
        print(f"floorscan map-log: poses by odometry: {_describe(summary)}", file=sys.stderr)
    rays, cells, seconds = map_lasers(
        grid,
        lasers,
        max_range_m=args.max_range,
        min_range_m=args.min_range,
        clear_no_return=args.no_return == "clear",
    )
    grid.save(args.output, mode=args.mode)
    if args.trajectory:
        write_tum(args.trajectory, robot_trajectory(log.lasers, lasers))
        if args.poses == "odometry":
            odometry = log_odometry(log).robot_poses
            write_tum(
                odometry_path(args.trajectory),
                Trajectory.from_increasing((r.timestamp, *p) for r, p in zip(log.lasers, odometry)),
            )
    if args.png:
        grid.to_png(args.png, scale=args.png_scale)
    e = grid.extent
    (x0, y0), (x1, y1) = e.bounds_m
    print(
        f"mapped {len(log.lasers)} scans, {rays} rays, {cells} cells traversed in {seconds:.3f} s "
        f"({rays / max(seconds, 1e-9):,.0f} rays/s, "
        f"{1e9 * seconds / max(cells, 1):.2f} ns per cell)\n"
        f"map {e.width} x {e.height} cells of {e.cell_size_m} m: "
        f"x {x0:.2f}..{x1:.2f}, y {y0:.2f}..{y1:.2f} m; "
        f"{grid.allocated_tiles} tiles, {grid.memory_bytes / 1e6:.1f} MB; "
        f"peak memory {peak_rss_mb():.1f} MB\n"
        f"-> {args.output}" + (f", {args.png}" if args.png else ""),
        file=sys.stderr,
    )
    return 0
