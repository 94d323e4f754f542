"""The robot's raw odometry at each laser reading of a CARMEN log, for mapping a log the way a
robot met it (dead reckoning, then scan matching) rather than at the poses a SLAM run wrote.

Two kinds of log:

- **Raw logs** (as recorded): every pose in the log is odometry's. The pose of a laser line
  (``FLASER``'s ``odom_*``, ``ROBOTLASER1``'s ``robot_*``) is the odometry at that scan.
- **Corrected logs** (written by a SLAM run, as Radish's ``*-corrected`` logs and
  ``../shared/data/carmen``): each laser line carries the corrected pose and is followed by an
  ``ODOM`` line with timestamp 0 at that pose (an *anchor*; the Intel log's last 70 scans
  write that 0 as garbage, a denormal such as ``1.08499e-42`` or a value such as ``1.13``: an
  anchor is the first ``ODOM`` line after a laser line whose timestamp is below
  :data:`ANCHOR_TIMESTAMP_S`, or which repeats the laser line's pose with a timestamp more than
  :data:`ANCHOR_LAG_S` before the scan's); the ``ODOM`` lines after it go on
  with raw odometry, moved so that it starts at the anchor. Odometry's own motion from scan k to
  scan k + 1 is therefore ``inverse(anchor_k) * last ODOM before scan k + 1``, and chaining those
  motions from the first scan's pose rebuilds the dead-reckoned path. Where no ``ODOM`` line
  lies between two scans, the motion is the last odometry velocities (``tv``, ``rv``) over the
  scans' time difference (none before any velocity is known).

The poses returned are the robot's; each laser's pose follows from it by the mount offset its
line states (``inverse(robot pose) * laser pose``, identity for a laser at the robot's origin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional

import numpy as np

from ..errors import DatasetError
from .carmen import CarmenLog, OdometryReading, Pose
from .trajectory import compose, inverse

ANCHOR_TIMESTAMP_S = 1e-9
"""An ``ODOM`` line's timestamp below this [s] marks an anchor (0, or a denormal written for
it); a recorded timestamp counts seconds and is never this small."""
ANCHOR_LAG_S = 1.0
"""An ``ODOM`` line at the scan's pose stamped this much [s] before the scan is an anchor
with a garbage timestamp (odometry recorded after a scan is not stamped before it)."""


def _is_anchor(o: OdometryReading, laser) -> bool:
    """Whether ``o``, the first ``ODOM`` line after ``laser``'s line, is its anchor."""
    if abs(o.timestamp) < ANCHOR_TIMESTAMP_S:
        return True
    at_scan = any(
        all(abs(a - b) <= 1e-6 for a, b in zip(o.pose, pose))
        for pose in (laser.robot_pose, laser.laser_pose)
    )
    return at_scan and o.timestamp < laser.timestamp - ANCHOR_LAG_S


@dataclass(frozen=True)
class LogOdometry:
    """Odometry at each laser reading of a log."""

    robot_poses: np.ndarray
    """(N, 3) the robot's odometry pose (x [m], y [m], yaw [rad]) at each laser reading, in
    the log's frame at the first reading."""
    laser_poses: np.ndarray
    """(N, 3) the laser's pose by odometry (the robot's, moved by the line's mount offset)."""
    rebuilt: bool
    """True for a corrected log (odometry chained from its anchors), False for a raw one."""
    extrapolated: int
    """Scan-to-scan motions taken from velocities (no ``ODOM`` line between the two scans)."""


def log_odometry(log: CarmenLog) -> LogOdometry:
    """The raw odometry at each of ``log``'s laser readings (see the module docs)."""
    if not log.lasers:
        raise DatasetError(f"{log.source}: no laser lines to give odometry for")
    events = sorted(
        [(r.line, 0, i) for i, r in enumerate(log.lasers)]
        + [(o.line, 1, j) for j, o in enumerate(log.odometry)]
    )
    # ODOM lines after each laser line, up to the next one.
    after: List[List[OdometryReading]] = [[] for _ in log.lasers]
    current: Optional[int] = None
    for _line, kind, index in events:
        if kind == 0:
            current = index
        elif current is not None:
            after[current].append(log.odometry[index])
    anchored = [bool(a) and _is_anchor(a[0], r) for a, r in zip(after, log.lasers)]
    rebuilt = any(anchored)
    offsets = [compose(inverse(r.robot_pose), r.laser_pose) for r in log.lasers]
    if not rebuilt:
        robot = np.array([r.robot_pose for r in log.lasers], np.float64)
        return LogOdometry(robot, _laser_poses(robot, offsets), False, 0)
    poses: List[Pose] = [tuple(log.lasers[0].robot_pose)]
    velocity = (0.0, 0.0)
    extrapolated = 0
    for k in range(len(log.lasers) - 1):
        segment = after[k]
        raw = segment[1:] if anchored[k] else segment
        if anchored[k] and raw:
            motion = compose(inverse(segment[0].pose), raw[-1].pose)
            velocity = (raw[-1].tv, raw[-1].rv)
        else:
            # No odometry between the two scans: the last velocities over the time between.
            if raw:
                velocity = (raw[-1].tv, raw[-1].rv)
            dt = max(0.0, log.lasers[k + 1].timestamp - log.lasers[k].timestamp)
            motion = _arc(velocity[0] * dt, velocity[1] * dt)
            extrapolated += 1
        poses.append(compose(poses[-1], motion))
    robot = np.array(poses, np.float64)
    return LogOdometry(robot, _laser_poses(robot, offsets), True, extrapolated)


def _arc(distance_m: float, turn_rad: float) -> Pose:
    """The motion along a circular arc of this length and turn."""
    if abs(turn_rad) < 1e-9:
        return (distance_m, 0.0, 0.0)
    r = distance_m / turn_rad
    return (r * math.sin(turn_rad), r * (1.0 - math.cos(turn_rad)), turn_rad)


def _laser_poses(robot: np.ndarray, offsets) -> np.ndarray:
    return np.array([compose(tuple(p), o) for p, o in zip(robot, offsets)], np.float64)
