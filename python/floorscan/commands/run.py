"""``floorscan run``: the main job. Camera frames and odometry in (dataset folder, video file,
live camera, ROS 1/2 bag), range scans and occupancy maps out (see run_outputs.py)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..calibration import calibrate
from ..errors import DatasetError, OptionError
from ..formats.image_io import read_grey, set_max_image_pixels
from ..formats.rig import Rig
from ..pipeline.config import Config, default_value
from ..pipeline.config_check import check_config
from ..pipeline.mapper import RANGER_KINDS, Mapper, run
from ..pipeline.outputs import RunOutputs
from ..pipeline.progress import Progress
from ..pipeline.sources import BagSource, CameraSource, DatasetSource, FrameSource, VideoSource
from ..ranging.ground_table import GroundTable
from ._help import config_default
from ._output import FOLDER, add_output

VIDEO_SUFFIXES = {".mp4", ".avi", ".mkv", ".mov", ".webm", ".m4v", ".mpg", ".mpeg"}


def register(sub) -> None:
    columns = default_value("ranger.columns")
    p = sub.add_parser("run", help="images + odometry in, scans and occupancy maps out")
    p.add_argument(
        "input", nargs="?", help="dataset folder, video file, ROS 1 .bag or ROS 2 bag folder"
    )
    add_output(p, FOLDER, "output folder")
    p.add_argument("--table", help="ground table JSON (from `floorscan calibrate`)")
    p.add_argument(
        "--calibrate",
        metavar="PATTERN_IMAGE",
        help="calibrate from this image first (pattern TOML beside it, or --pattern)",
    )
    p.add_argument("--pattern", help="pattern TOML for --calibrate")
    p.add_argument("--config", help="configuration TOML (floorscan config --default)")
    p.add_argument("--odometry", help="TUM odometry file (video or live input)")
    p.add_argument(
        "--camera",
        type=int,
        metavar="DEVICE",
        help="live camera (OpenCV device index) instead of INPUT",
    )
    p.add_argument("--max-frames", type=int, help="stop after this many frames (live input)")
    p.add_argument(
        "--image-topic",
        default="/camera/image_raw",
        help="bag image topic (Image or CompressedImage) (default %(default)s)",
    )
    p.add_argument(
        "--odom-topic",
        default="/odom",
        help="bag odometry topic (nav_msgs/Odometry) (default %(default)s)",
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="fail on an unreadable frame or missing odometry instead of skipping it",
    )
    p.add_argument(
        "--rerun", action="store_true", help="also log to a Rerun recording (needs rerun-sdk)"
    )
    p.add_argument(
        "--threshold", type=float, help="least edge threshold " + config_default("ranger.threshold")
    )
    p.add_argument(
        "--half-width-px",
        "--half-width",
        dest="half_width_px",
        type=int,
        help="box filter half-width d [px] " + config_default("ranger.half_width_px"),
    )
    p.add_argument(
        "--columns",
        type=int,
        help="number of evenly spaced columns (default: placed so that no obstacle "
        f"{columns['obstacle_width_m']} m wide at {columns['range_m']} m stands between two, "
        "the config's ranger.columns)",
    )
    p.add_argument(
        "--ranger", choices=RANGER_KINDS, help="range sensor " + config_default("ranger.kind")
    )
    p.set_defaults(run=main)


def open_source(args: argparse.Namespace) -> FrameSource:
    if args.camera is not None:
        return CameraSource(args.camera, odometry=args.odometry, max_frames=args.max_frames)
    if not args.input:
        raise OptionError("give an INPUT (dataset folder, video, bag) or --camera DEVICE")
    path = Path(args.input)
    if not path.exists():
        raise DatasetError(f"input not found: {path}")
    if path.is_dir() and (path / "images.txt").is_file():
        return DatasetSource(path)
    if path.suffix == ".bag" or (path.is_dir() and (path / "metadata.yaml").is_file()):
        return BagSource(path, image_topic=args.image_topic, odom_topic=args.odom_topic)
    if path.is_file() and path.suffix.lower() in VIDEO_SUFFIXES:
        return VideoSource(path, odometry=args.odometry)
    raise DatasetError(
        f"{path}: not a dataset folder (images.txt), a bag or a video file ({', '.join(sorted(VIDEO_SUFFIXES))})"
    )


def load_table(args: argparse.Namespace, source: FrameSource, cfg: Config) -> GroundTable:
    if args.table:
        return GroundTable.load(args.table)
    image_path = Path(args.calibrate) if args.calibrate else None
    if (
        image_path is None
        and isinstance(source, DatasetSource)
        and (source.folder / "calibration" / "pattern.png").is_file()
    ):
        image_path = source.folder / "calibration" / "pattern.png"
    if image_path is None:
        raise OptionError("no calibration: give --table TABLE.json or --calibrate PATTERN_IMAGE")
    pattern = Path(args.pattern) if args.pattern else image_path.with_name("pattern.toml")
    table, report = calibrate(
        read_grey(image_path),
        pattern,
        **cfg.calibration.kwargs(),
    )
    print(f"calibrated from {image_path}: {report.summary()}", file=sys.stderr)
    return table


def rig_pose(source: FrameSource, cfg: Config):
    rig = source.rig or Rig()
    r = cfg.rig
    return (
        r.x if r.x is not None else rig.x,
        r.y if r.y is not None else rig.y,
        r.yaw if r.yaw is not None else rig.yaw,
    )


def nothing_mapped(stats, out) -> str:
    """Why a run that ended normally mapped no frame, in one line."""
    if stats.frames_in == 0:
        return f"the input holds no frames: nothing was mapped (outputs in {out}/)"
    reasons = ", ".join(
        f"{n} {why}"
        for why, n in (
            ("unreadable", stats.skipped_unreadable),
            ("without odometry at their time", stats.skipped_no_odometry),
            ("of another size than the table's", stats.skipped_wrong_size),
            ("outside the map", stats.skipped_out_of_map),
        )
        if n
    )
    return (
        f"none of the {stats.frames_in} frames could be mapped ({reasons or 'all skipped'}); "
        f"outputs in {out}/"
    )


def main(args: argparse.Namespace) -> int:
    cfg = Config.load(args.config) if args.config else Config()
    cfg = cfg.with_overrides(
        {
            "ranger.threshold": args.threshold,
            "ranger.half_width_px": args.half_width_px,
            "ranger.columns": args.columns,
            "ranger.kind": args.ranger,
        }
    )
    check_config(cfg)
    set_max_image_pixels(cfg.limits.max_image_pixels)
    source = open_source(args)
    table = load_table(args, source, cfg)
    mapper = Mapper(table, cfg, robot_from_camera=rig_pose(source, cfg))
    outputs = None
    try:
        outputs = RunOutputs(args.output, cfg, expected_frames=len(source) or None)
        if args.rerun:
            from ..pipeline.rerun_log import RerunOutputs

            outputs = RerunOutputs(outputs)
        if source.odometry is None:
            print(
                "no odometry: only the local map is built (the robot is taken as standing still)",
                file=sys.stderr,
            )
        stats = run(
            source, mapper, outputs, strict=args.strict, progress=Progress(len(source) or None)
        )
    except BaseException:
        if outputs is not None and not getattr(outputs, "finishing", True):
            outputs.discard()  # stopped before the run began: nothing to save, nothing left
        raise
    skipped = stats.frames_in - stats.frames_mapped
    if not stats.interrupted and stats.frames_mapped == 0:
        # The outputs are written (they say what happened); the exit status says it too.
        raise DatasetError(
            nothing_mapped(stats, outputs.out if hasattr(outputs, "out") else args.output)
        )
    print(
        f"{stats.frames_mapped} frames mapped, {skipped} skipped, {stats.boundary_points} boundary points"
        + (" (interrupted: map saved)" if stats.interrupted else "")
    )
    print(
        f"outputs in {outputs.out if hasattr(outputs, 'out') else args.output}/: map.yaml map.png scans.csv summary.json ..."
    )
    return 128 + (stats.signal or 2) if stats.interrupted else 0
