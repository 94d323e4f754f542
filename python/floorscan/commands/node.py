"""``floorscan node``: live on a robot. Camera and odometry topics in, LaserScan and
OccupancyGrid topics out, over ROS 1 (rospy) or ROS 2 (rmw_zenoh); every output of
``floorscan run`` saved in the output folder when it stops (Ctrl-C, SIGTERM, SIGHUP)."""

from __future__ import annotations

import argparse

from ..formats.image_io import set_max_image_pixels
from ..node import NodeRun
from ..pipeline.config import Config
from ..ranging.ground_table import GroundTable
from ._help import config_default
from ._output import FOLDER, add_output


def register(sub) -> None:
    p = sub.add_parser(
        "node", help="live ROS 1 / ROS 2 node: camera + odometry in, /scan and /map out"
    )
    p.add_argument("--table", required=True, help="ground table JSON (from `floorscan calibrate`)")
    add_output(p, FOLDER, "folder for the outputs saved on stop")
    p.add_argument(
        "--config", help="configuration TOML (its [node] table: topics, frames, transport)"
    )
    p.add_argument(
        "--transport",
        choices=["ros1", "zenoh"],
        help="middleware " + config_default("node.transport"),
    )
    p.add_argument("--image-topic", help="camera topic " + config_default("node.image_topic"))
    p.add_argument(
        "--odom-topic",
        help='odometry topic, "" for none ' + config_default("node.odom_topic"),
    )
    p.add_argument("--compressed", action="store_true", help="the image topic is CompressedImage")
    p.add_argument("--max-frames", type=int, help="stop after this many frames")
    p.add_argument(
        "--foxglove",
        type=int,
        metavar="PORT",
        help="live view: a Foxglove WebSocket server on 127.0.0.1:PORT, 0 for none "
        + config_default("node.foxglove_port"),
    )
    p.set_defaults(run=main)


def main(args: argparse.Namespace) -> int:
    cfg = Config.load(args.config) if args.config else Config()
    cfg = cfg.with_overrides(
        {
            "node.transport": args.transport,
            "node.image_topic": args.image_topic,
            "node.odom_topic": args.odom_topic,
            "node.compressed": True if args.compressed else None,
            "node.foxglove_port": args.foxglove,
        }
    )
    set_max_image_pixels(cfg.limits.max_image_pixels)
    table = GroundTable.load(args.table)
    r = cfg.rig
    mount = (r.x or 0.0, r.y or 0.0, r.yaw or 0.0)
    node = NodeRun(table, cfg, args.output, robot_from_camera=mount, max_frames=args.max_frames)
    stats = node.run()
    print(
        f"{stats.frames_mapped} frames mapped, {stats.frames_in - stats.frames_mapped} skipped, "
        f"{stats.dropped_live} dropped; outputs in {args.output}/"
        + (" (stopped by signal: map saved)" if stats.interrupted else "")
    )
    return 128 + (stats.signal or 2) if stats.interrupted else 0
