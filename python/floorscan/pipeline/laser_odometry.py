"""A laser log mapped the way its robot met it: from raw odometry
(:func:`~floorscan.formats.carmen_odometry.log_odometry`), with loop closure over a pose graph
when ``[slam]`` is in graph mode (:class:`~floorscan.pipeline.graph_slam.GraphSlam`), each scan
matched against the scans before it in local mode (the same matcher and filter as camera runs,
:class:`~floorscan.pipeline.pose_correction.PoseCorrection`), or dead reckoning with ``mode =
"off"``. ``floorscan map-log --poses odometry`` uses it."""

from __future__ import annotations

import dataclasses
import math
from typing import Dict, List, Tuple

import numpy as np

from ..formats.carmen import CarmenLog, LaserReading
from ..formats.carmen_odometry import log_odometry
from ..formats.trajectory import compose, inverse
from .config import Config
from .graph_slam import GraphSlam
from .pose_correction import PoseCorrection


def beam_ends_robot(reading: LaserReading, range_max_m: float, range_min_m: float) -> np.ndarray:
    """(N, 2) [m] the ends of a scan's returns (ranges in (range_min_m, range_max_m)) in the
    robot frame (the laser's mount offset as its line states it)."""
    r = reading.ranges
    a = reading.angle_min + np.arange(r.size) * reading.angle_increment
    ok = np.isfinite(r) & (r > range_min_m) & (r < range_max_m)
    x, y = r[ok] * np.cos(a[ok]), r[ok] * np.sin(a[ok])
    ox, oy, oyaw = compose(inverse(reading.robot_pose), reading.laser_pose)
    c, s = math.cos(oyaw), math.sin(oyaw)
    return np.stack([ox + c * x - s * y, oy + s * x + c * y], axis=1)


def graph_of(
    log: CarmenLog, robot_poses, cfg: Config, *, range_max_m: float, range_min_m: float
) -> GraphSlam:
    """The pose graph (``[slam.graph]``) of the log's scans at odometry's ``robot_poses`` (N,
    3), every scan added, not yet finished (its graph as built, before the last solve)."""
    slam = GraphSlam(cfg.slam.options()["graph"])
    reach = min(range_max_m, slam.options.range_max_m)
    for r, p in zip(log.lasers, robot_poses):
        slam.add(beam_ends_robot(r, reach, range_min_m), tuple(p))
    return slam


def lasers_at_odometry(
    log: CarmenLog, cfg: Config, *, range_max_m: float, range_min_m: float
) -> Tuple[List[LaserReading], Dict[str, object]]:
    """The log's laser readings with their laser poses replaced by odometry's (matched when
    ``cfg.slam.mode`` is ``local``; optimised over a pose graph when it is ``graph``), and a
    summary: how odometry was found, frames matched,
    the final correction."""
    odometry = log_odometry(log)
    summary: Dict[str, object] = {
        "odometry": "rebuilt from the log's anchors" if odometry.rebuilt else "as logged",
        "odometry_extrapolated": odometry.extrapolated,
        "slam": cfg.slam.mode,
    }
    robot = odometry.robot_poses
    if cfg.slam.mode == "graph":
        slam = graph_of(
            log, odometry.robot_poses, cfg, range_max_m=range_max_m, range_min_m=range_min_m
        )
        robot = slam.finish()
        end = compose(tuple(robot[-1]), inverse(tuple(odometry.robot_poses[-1])))
        summary.update(slam.summary())
        summary["final_correction_m"] = math.hypot(end[0], end[1])
        summary["final_correction_rad"] = math.remainder(end[2], 2 * math.pi)
    elif cfg.slam.mode == "local":
        correction = PoseCorrection(cfg.slam.options()["matcher"])
        # The matcher's reach, as a camera's scan has it (its points beyond are not matched).
        reach = min(range_max_m, correction.options.range_max_m)
        robot = np.array(
            [
                correction.correct_points(
                    beam_ends_robot(r, reach, range_min_m), tuple(p), timestamp=r.timestamp
                )
                for r, p in zip(log.lasers, odometry.robot_poses)
            ]
        )
        summary.update(correction.summary())
    lasers = [
        dataclasses.replace(
            r, laser_pose=compose(tuple(p), compose(inverse(r.robot_pose), r.laser_pose))
        )
        for r, p in zip(log.lasers, robot)
    ]
    return lasers, summary
