"""Scans: one frame's readings, one per sampled column, and the public scans CSV.

CSV contract (header ``timestamp,column,row,status,x,y,range,bearing``): one line per column
reading; ``status`` is ``boundary``, ``no_boundary``, ``too_close`` or ``invalid``; ``x``/``y``
[m] are in the camera ground frame; ``range`` [m] follows REP 117 (+inf no return, -inf too
close, nan invalid); ``bearing`` [rad] is ``atan2(y, x)``. See docs/formats.md.
"""

from __future__ import annotations

import csv
import enum
import io
import math
from pathlib import Path
from typing import Dict, Iterable, Iterator, List

import numpy as np

from .._atomic import PathLike, write_atomic
from .._native import ranging as _native
from ..errors import FileFormatError

SCAN_CSV_HEADER: str = _native.SCAN_CSV_HEADER
"""The scans CSV header (floorscan-core's ``scan::SCAN_CSV_HEADER``)."""

ColumnStatus = enum.IntEnum(
    "ColumnStatus", {name.upper(): code for name, code in _native.column_statuses()}
)
ColumnStatus.__doc__ = """What a column saw (floorscan-core's ``ColumnStatus``, built from it): the
values are the codes of :attr:`Scan.status_codes`, the lower-case names the CSV's ``status``.

>>> ColumnStatus.BOUNDARY == 0, ColumnStatus(3).name.lower()
(True, 'invalid')
"""

STATUS_NAMES = tuple(s.name.lower() for s in ColumnStatus)
"""Status names, indexed by the integer codes of :attr:`Scan.status_codes`."""


class Scan:
    """The readings of one frame (arrays of equal length, one entry per sampled column).

    Attributes are numpy arrays: ``columns`` (uint32, image column u [px]), ``rows`` (float64,
    boundary row v [px], v = 0 at the top), ``status`` (str names), ``status_codes`` (uint8),
    ``x``/``y`` (float64 [m], camera ground frame), ``ranges`` [m] (REP 117), ``bearings``
    [rad], ``near_x``/``near_y`` [m] (nearest floor the column sees: where the map builder
    starts free space).
    """

    __slots__ = ("_native",)

    def __init__(self, native: _native.Scan) -> None:
        self._native = native

    @property
    def timestamp(self) -> float:
        """Frame time [s]."""
        return self._native.timestamp

    def __len__(self) -> int:
        return len(self._native)

    columns = property(lambda self: self._native.columns)
    rows = property(lambda self: self._native.rows)
    status_codes = property(lambda self: self._native.status_codes)
    x = property(lambda self: self._native.x)
    y = property(lambda self: self._native.y)
    ranges = property(lambda self: self._native.ranges)
    bearings = property(lambda self: self._native.bearings)
    near_x = property(lambda self: self._native.near_x)
    near_y = property(lambda self: self._native.near_y)
    confidence = property(lambda self: self._native.confidence)
    """How sure the ranger is of each reading, in [0, 1] (float32): edge ranger, how far the
    edge cleared the threshold; appearance ranger, the floor / not-floor margin."""
    footprints = property(lambda self: self._native.footprints)
    """Floor length one pixel row covers at each boundary [m]: the reading's range resolution."""

    @property
    def status(self) -> np.ndarray:
        """Status names (``boundary``, ``no_boundary``, ``too_close``, ``invalid``)."""
        return np.array(STATUS_NAMES, dtype=object)[self.status_codes]

    def count(self) -> Dict[str, int]:
        """Number of columns per status."""
        codes = np.bincount(self.status_codes, minlength=4)
        return {name: int(n) for name, n in zip(STATUS_NAMES, codes)}

    def to_laser_scan(
        self, *, angle_min: float, angle_max: float, angle_increment: float
    ) -> Dict[str, object]:
        """Fixed angular binning with the fields of ``sensor_msgs/LaserScan`` [rad, m]: the
        nearest boundary per bin, +inf for no return (REP 117)."""
        return self._native.to_laser_bins(
            float(angle_min), float(angle_max), float(angle_increment)
        )

    def csv_lines(self) -> str:
        """The scan's lines of the public CSV, without the header."""
        return self._native.csv_lines()

    @classmethod
    def from_arrays(
        cls,
        *,
        timestamp: float,
        columns,
        rows,
        status,
        x,
        y,
        near_x=None,
        near_y=None,
    ) -> Scan:
        """Builds a scan from arrays (``status`` as names or codes)."""
        status = np.asarray(status)
        if status.dtype.kind in "US" or status.dtype == object:
            lookup = {name: code for code, name in enumerate(STATUS_NAMES)}
            try:
                codes = np.array([lookup[str(s)] for s in status], dtype=np.uint8)
            except KeyError as e:
                raise FileFormatError(f"unknown column status {e.args[0]!r}") from None
        else:
            codes = status.astype(np.uint8)
        n = len(codes)
        nan = np.full(n, np.nan)
        return cls(
            _native.Scan.from_arrays(
                float(timestamp),
                np.ascontiguousarray(columns, dtype=np.uint32),
                np.ascontiguousarray(rows, dtype=np.float64),
                codes,
                np.ascontiguousarray(x, dtype=np.float64),
                np.ascontiguousarray(y, dtype=np.float64),
                nan if near_x is None else np.ascontiguousarray(near_x, dtype=np.float64),
                nan if near_y is None else np.ascontiguousarray(near_y, dtype=np.float64),
            )
        )

    def __repr__(self) -> str:
        return f"Scan(t={self.timestamp}, {len(self)} columns, {self.count()})"


def scans_to_csv(scans: Iterable[Scan]) -> str:
    """The public CSV text (header and lines) of a sequence of scans."""
    parts: List[str] = [SCAN_CSV_HEADER + "\n"]
    parts.extend(s.csv_lines() for s in scans)
    return "".join(parts)


def write_scans_csv(path: PathLike, scans: Iterable[Scan]) -> Path:
    """Writes scans to the public CSV, atomically."""
    return write_atomic(path, scans_to_csv(scans))


def read_scans_csv(path: PathLike) -> List[Scan]:
    """Reads the public CSV back into scans (one per timestamp, in file order)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise FileFormatError(f"cannot read scans CSV {path}: {e}") from None
    return list(parse_scans_csv(text, source=str(path)))


def parse_scans_csv(text: str, *, source: str = "<csv>") -> Iterator[Scan]:
    """The scans of CSV text (FileFormatError naming the line for anything malformed)."""
    try:
        yield from _parse_scans_csv(text, source)
    except csv.Error as e:
        raise FileFormatError(f"{source}: not a valid CSV file: {e}") from None


def _parse_scans_csv(text: str, source: str) -> Iterator[Scan]:
    reader = csv.reader(io.StringIO(text, newline=""))
    header = next(reader, None)
    if header is None or ",".join(h.strip() for h in header) != SCAN_CSV_HEADER:
        raise FileFormatError(f"{source}: first line must be the header {SCAN_CSV_HEADER!r}")
    rows: List[List[str]] = []
    current = None
    previous_t = -math.inf
    for lineno, fields in enumerate(reader, start=2):
        if not fields:
            continue
        if len(fields) != 8:
            raise FileFormatError(f"{source}:{lineno}: expected 8 fields, got {len(fields)}")
        if current is not None and fields[0] != current:
            scan = _scan_from_rows(rows, source)
            previous_t = _in_time_order(scan, previous_t, source, rows[0][-1])
            yield scan
            rows = []
        current = fields[0]
        rows.append(fields + [str(lineno)])
    if rows:
        scan = _scan_from_rows(rows, source)
        _in_time_order(scan, previous_t, source, rows[0][-1])
        yield scan


def _in_time_order(scan: Scan, previous_t: float, source: str, lineno: str) -> float:
    """The scans of a CSV are in increasing time order (docs/formats.md)."""
    if not math.isfinite(scan.timestamp):
        raise FileFormatError(f"{source}:{lineno}: timestamp {scan.timestamp} is not finite")
    if scan.timestamp <= previous_t:
        raise FileFormatError(
            f"{source}:{lineno}: scan at t={scan.timestamp} is not after the previous one "
            f"(t={previous_t}): scans must be in increasing time order"
        )
    return scan.timestamp


def _scan_from_rows(rows: List[List[str]], source: str) -> Scan:
    try:
        t = float(rows[0][0])
        cols = [int(r[1]) for r in rows]
        vals = np.array([[float(r[2]), float(r[4]), float(r[5])] for r in rows], dtype=np.float64)
    except ValueError as e:
        raise FileFormatError(f"{source}:{rows[0][-1]}: {e}") from None
    status = [r[3] for r in rows]
    return Scan.from_arrays(
        timestamp=t, columns=cols, rows=vals[:, 0], status=status, x=vals[:, 1], y=vals[:, 2]
    )
