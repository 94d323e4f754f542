"""Planar trajectories in TUM format, and odometry matched to frame times.

TUM format: one pose per line, ``timestamp tx ty tz qx qy qz qw`` (``#`` comments allowed). The
robot moves in the plane: z is ignored on reading and written as 0; yaw is taken from the
quaternion (REP 103: counter-clockwise about +z, radians).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, List, Optional, Tuple

import numpy as np

from .._atomic import PathLike, write_atomic
from ..errors import DatasetError, GeometryError

MIN_QUATERNION_NORM = 1e-6
"""Quaternions shorter than this are refused (no rotation can be read from them); any longer
quaternion is normalised (the yaw formula below is invariant to its scale)."""


def compose(a, b) -> Tuple[float, float, float]:
    """``a`` then ``b`` for planar poses (x [m], y [m], yaw [rad]): ``world_from_robot`` composed
    with ``robot_from_camera`` is ``world_from_camera``. The yaw is not wrapped."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def inverse(p) -> Tuple[float, float, float]:
    """The inverse of the planar transform ``p`` (x [m], y [m], yaw [rad]): ``compose(p,
    inverse(p))`` is the identity."""
    c, s = math.cos(p[2]), math.sin(p[2])
    return (-c * p[0] - s * p[1], s * p[0] - c * p[1], -p[2])


def relative(a, b) -> Tuple[float, float, float]:
    """``b`` seen from ``a`` (``compose(inverse(a), b)``), the yaw wrapped to [-pi, pi]: the
    motion from pose ``a`` to pose ``b``."""
    x, y, yaw = compose(inverse(a), b)
    return (x, y, math.remainder(yaw, 2 * math.pi))


def yaw_from_quaternion(qx: float, qy: float, qz: float, qw: float) -> float:
    """Yaw [rad] about +z of a quaternion, normalised first (GeometryError if near zero)."""
    norm = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    if not norm >= MIN_QUATERNION_NORM:
        raise GeometryError(f"quaternion ({qx}, {qy}, {qz}, {qw}) has norm {norm}: not a rotation")
    # atan2(2(wz + xy), w^2 + x^2 - y^2 - z^2) equals the unit-quaternion formula
    # atan2(2(wz + xy), 1 - 2(y^2 + z^2)) for |q| = 1 and does not depend on |q|.
    return math.atan2(2.0 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz)


def quaternion_from_yaw(yaw: float) -> Tuple[float, float, float, float]:
    """(qx, qy, qz, qw) of a rotation by ``yaw`` about +z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


@dataclass(frozen=True)
class Pose2:
    """A planar pose [m, m, rad]; as a transform ``world_from_robot``."""

    x: float
    y: float
    yaw: float

    def as_tuple(self) -> Tuple[float, float, float]:
        return (self.x, self.y, self.yaw)


class Trajectory:
    """Time-stamped planar poses with strictly increasing timestamps [s]."""

    def __init__(self, timestamps, x, y, yaw) -> None:
        self.timestamps = np.asarray(timestamps, dtype=np.float64)
        self.x = np.asarray(x, dtype=np.float64)
        self.y = np.asarray(y, dtype=np.float64)
        self.yaw = np.asarray(yaw, dtype=np.float64)
        n = len(self.timestamps)
        if not (len(self.x) == len(self.y) == len(self.yaw) == n):
            raise GeometryError("trajectory arrays must have the same length")
        arrays = (self.timestamps, self.x, self.y, self.yaw)
        if not all(np.all(np.isfinite(a)) for a in arrays):
            raise GeometryError("trajectory values must be finite")
        if n > 1 and np.any(np.diff(self.timestamps) <= 0):
            i = int(np.argmax(np.diff(self.timestamps) <= 0))
            raise GeometryError(
                f"trajectory timestamps must increase (pose {i + 1}: {self.timestamps[i + 1]} after {self.timestamps[i]})"
            )

    def __len__(self) -> int:
        return len(self.timestamps)

    @property
    def time_range(self) -> Optional[Tuple[float, float]]:
        return None if len(self) == 0 else (float(self.timestamps[0]), float(self.timestamps[-1]))

    def pose_at(self, t: float) -> Optional[Pose2]:
        """Pose at time ``t`` by linear interpolation (yaw along the shorter arc); ``None``
        outside the trajectory's time range (never extrapolated)."""
        ts = self.timestamps
        if len(ts) == 0 or not (ts[0] <= t <= ts[-1]):
            return None
        i = int(np.searchsorted(ts, t, side="right")) - 1
        if i >= len(ts) - 1:
            return Pose2(float(self.x[-1]), float(self.y[-1]), float(self.yaw[-1]))
        a = (t - ts[i]) / (ts[i + 1] - ts[i])
        dyaw = math.remainder(self.yaw[i + 1] - self.yaw[i], 2.0 * math.pi)
        return Pose2(
            float(self.x[i] + a * (self.x[i + 1] - self.x[i])),
            float(self.y[i] + a * (self.y[i + 1] - self.y[i])),
            math.remainder(float(self.yaw[i] + a * dyaw), 2.0 * math.pi),
        )

    @classmethod
    def from_increasing(cls, stamped: Iterable[Tuple[float, float, float, float]]) -> Trajectory:
        """As :meth:`from_poses`, leaving out each pose whose timestamp does not increase
        on the last one kept (a log whose clock stood still)."""
        kept: List[Tuple[float, float, float, float]] = []
        for r in stamped:
            if not kept or r[0] > kept[-1][0]:
                kept.append(tuple(r))
        return cls.from_poses(kept)

    @classmethod
    def from_poses(cls, stamped: Iterable[Tuple[float, float, float, float]]) -> Trajectory:
        rows = list(stamped)
        if not rows:
            return cls([], [], [], [])
        a = np.asarray(rows, dtype=np.float64)
        return cls(a[:, 0], a[:, 1], a[:, 2], a[:, 3])


def read_tum(path: PathLike) -> Trajectory:
    """Reads a TUM trajectory file; malformed lines raise DatasetError naming the line."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise DatasetError(f"cannot read trajectory {path}: {e}") from None
    rows: List[Tuple[float, float, float, float]] = []
    for lineno, line in enumerate(lines, start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split()
        if len(parts) != 8:
            raise DatasetError(
                f"{path}:{lineno}: expected 8 values 'timestamp tx ty tz qx qy qz qw', got {len(parts)}"
            )
        try:
            t, tx, ty, _tz, qx, qy, qz, qw = (float(p) for p in parts)
        except ValueError:
            raise DatasetError(f"{path}:{lineno}: not a number in {line!r}") from None
        if not all(math.isfinite(v) for v in (t, tx, ty, qx, qy, qz, qw)):
            raise DatasetError(f"{path}:{lineno}: values must be finite")
        if rows and t <= rows[-1][0]:
            raise DatasetError(
                f"{path}:{lineno}: timestamp {t} does not increase (previous {rows[-1][0]})"
            )
        try:
            yaw = yaw_from_quaternion(qx, qy, qz, qw)
        except GeometryError as e:
            raise DatasetError(f"{path}:{lineno}: {e}") from None
        rows.append((t, tx, ty, yaw))
    return Trajectory.from_poses(rows)


def tum_text(trajectory: Trajectory) -> str:
    out = ["# timestamp tx ty tz qx qy qz qw\n"]
    for t, x, y, yaw in zip(trajectory.timestamps, trajectory.x, trajectory.y, trajectory.yaw):
        qx, qy, qz, qw = quaternion_from_yaw(float(yaw))
        out.append(f"{t:.6f} {x:.6f} {y:.6f} 0 {qx:.9f} {qy:.9f} {qz:.9f} {qw:.9f}\n")
    return "".join(out)


def write_tum(path: PathLike, trajectory: Trajectory) -> Path:
    """Writes a TUM trajectory file, atomically."""
    return write_atomic(path, tum_text(trajectory))
