"""CARMEN log files (plain or gzip): laser scans (``FLASER``, ``ROBOTLASER1``) and odometry
(``ODOM``); every other message type is counted and skipped.

Line formats (ranges [m], angles [rad], poses ``x y theta`` in the log's world frame):

- ``FLASER n r1 .. rn x y theta odom_x odom_y odom_theta timestamp hostname logger_timestamp``:
  a front laser with beams evenly spread over 180 degrees from -90 degrees (``n`` even: step
  pi / n, as 180 or 360 beams; ``n`` odd: step pi / (n - 1), as 181 or 361 beams). ``x y theta``
  is the laser's pose, ``odom_*`` the robot's odometry.
- ``ROBOTLASER1 laser_type start_angle fov angular_res max_range accuracy remission_mode n
  r1 .. rn n_remissions rem1 .. laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv
  forward_safety side_safety turn_axis timestamp hostname logger_timestamp``.
- ``ODOM x y theta tv rv accel timestamp hostname logger_timestamp``.

A malformed line of these three types is an error naming the file and line number
(:class:`~floorscan.DatasetError`), or, with ``strict=False``, is skipped and listed in
:attr:`CarmenLog.bad_lines`.
"""

from __future__ import annotations

import gzip
import io
import math
import zlib
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Tuple

import numpy as np

from .._atomic import PathLike
from ..errors import DatasetError

Pose = Tuple[float, float, float]


@dataclass(frozen=True)
class LaserReading:
    """One laser scan: ``ranges`` (B,) [m] with beam ``i`` at ``angle_min + i *
    angle_increment`` [rad] in the laser frame; ``laser_pose`` is ``world_from_laser``;
    ``max_range`` [m] if the log states it (ROBOTLASER1)."""

    kind: str
    line: int
    timestamp: float
    ranges: np.ndarray
    angle_min: float
    angle_increment: float
    laser_pose: Pose
    robot_pose: Pose
    max_range: Optional[float] = None


@dataclass(frozen=True)
class OdometryReading:
    line: int
    timestamp: float
    pose: Pose
    tv: float
    rv: float


@dataclass
class CarmenLog:
    """The messages of one log, in file order."""

    source: str
    lasers: List[LaserReading] = field(default_factory=list)
    odometry: List[OdometryReading] = field(default_factory=list)
    skipped: Dict[str, int] = field(default_factory=dict)
    bad_lines: List[Tuple[int, str]] = field(default_factory=list)


class _Fields:
    """Numbers of one line, with errors naming the field."""

    def __init__(self, parts: List[str], source: str, lineno: int) -> None:
        self.parts, self.source, self.lineno = parts, source, lineno

    def error(self, message: str) -> DatasetError:
        return DatasetError(f"{self.source}:{self.lineno}: {self.parts[0]}: {message}")

    def need(self, count: int) -> None:
        if len(self.parts) < count:
            raise self.error(
                f"expected at least {count} fields, got {len(self.parts)} (truncated line?)"
            )

    def number(self, i: int, name: str) -> float:
        try:
            v = float(self.parts[i])
        except (IndexError, ValueError):
            raise self.error(
                f"field {i} ({name}) is not a number: "
                f"{self.parts[i] if i < len(self.parts) else '<missing>'!r}"
            ) from None
        if math.isnan(v):
            raise self.error(f"field {i} ({name}) is NaN")
        return v

    def count(self, i: int, name: str) -> int:
        v = self.number(i, name)
        if not (0 <= v <= 100_000) or v != int(v):
            raise self.error(f"field {i} ({name}) must be a count, got {self.parts[i]!r}")
        return int(v)

    def numbers(self, start: int, n: int, name: str) -> np.ndarray:
        self.need(start + n)
        try:
            a = np.array(self.parts[start : start + n], dtype=np.float64)
        except ValueError:
            bad = next(p for p in self.parts[start : start + n] if not _is_number(p))
            raise self.error(f"a {name} value is not a number: {bad!r}") from None
        if np.isnan(a).any():
            raise self.error(f"{name} holds NaN")
        return a

    def pose(self, i: int, name: str) -> Pose:
        return (
            self.number(i, f"{name} x"),
            self.number(i + 1, f"{name} y"),
            self.number(i + 2, f"{name} theta"),
        )

    def expect_length(self, n: int) -> None:
        if len(self.parts) != n:
            raise self.error(f"expected {n} fields, got {len(self.parts)}")


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def _flaser(f: _Fields) -> LaserReading:
    f.need(2)
    n = f.count(1, "number of ranges")
    f.expect_length(2 + n + 9)
    ranges = f.numbers(2, n, "range")
    if n == 0:
        raise f.error("no ranges")
    step = math.pi / n if n % 2 == 0 else math.pi / max(n - 1, 1)
    laser = f.pose(2 + n, "laser pose")
    odom = f.pose(5 + n, "odometry pose")
    return LaserReading(
        "FLASER", f.lineno, f.number(8 + n, "timestamp"), ranges, -math.pi / 2, step, laser, odom
    )


def _robotlaser1(f: _Fields) -> LaserReading:
    f.need(9)
    start, _fov, res, max_range = (
        f.number(2, "start_angle"),
        f.number(3, "fov"),
        f.number(4, "angular_res"),
        f.number(5, "max_range"),
    )
    n = f.count(8, "number of ranges")
    ranges = f.numbers(9, n, "range")
    n_rem = f.count(9 + n, "number of remissions")
    tail = 10 + n + n_rem
    f.expect_length(tail + 14)
    if n == 0:
        raise f.error("no ranges")
    laser = f.pose(tail, "laser pose")
    robot = f.pose(tail + 3, "robot pose")
    return LaserReading(
        "ROBOTLASER1",
        f.lineno,
        f.number(tail + 11, "timestamp"),
        ranges,
        start,
        res,
        laser,
        robot,
        max_range,
    )


def _odom(f: _Fields) -> OdometryReading:
    f.expect_length(10)
    return OdometryReading(
        f.lineno, f.number(7, "timestamp"), f.pose(1, "pose"), f.number(4, "tv"), f.number(5, "rv")
    )


def parse_carmen_lines(
    lines: Iterable[str], *, source: str = "<log>", strict: bool = True
) -> CarmenLog:
    """Parses log lines (see the module docs)."""
    log = CarmenLog(source)
    skipped: Counter = Counter()
    for lineno, line in enumerate(lines, start=1):
        parts = line.split()
        if not parts or parts[0].startswith("#"):
            continue
        kind = parts[0]
        f = _Fields(parts, source, lineno)
        try:
            if kind == "FLASER":
                log.lasers.append(_flaser(f))
            elif kind == "ROBOTLASER1":
                log.lasers.append(_robotlaser1(f))
            elif kind == "ODOM":
                log.odometry.append(_odom(f))
            else:
                skipped[kind] += 1
        except DatasetError as e:
            if strict:
                raise
            log.bad_lines.append((lineno, str(e)))
    log.skipped = dict(skipped)
    return log


def read_carmen(path: PathLike, *, strict: bool = True) -> CarmenLog:
    """Reads a CARMEN log, gzip-compressed or not (detected from the content)."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            compressed = fh.read(2) == b"\x1f\x8b"
        raw = gzip.open(path, "rb") if compressed else open(path, "rb")
        # Streamed line by line: a log is never held in memory as a whole.
        with io.TextIOWrapper(raw, encoding="utf-8", errors="replace") as text:
            return parse_carmen_lines(text, source=str(path), strict=strict)
    except (OSError, EOFError, gzip.BadGzipFile, zlib.error) as e:
        raise DatasetError(f"cannot read CARMEN log {path}: {e}") from None
