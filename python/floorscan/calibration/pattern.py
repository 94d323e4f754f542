"""The calibration pattern on the floor and its ``pattern.toml`` description (a public contract,
shared with the simulator; docs/calibration.md and docs/dataset-format.md).

Ground frame: the camera ground frame (origin on the floor below the camera, x forward, y left,
metres, REP 103). The pattern's **away** axis is (cos yaw, sin yaw); its **across** axis is
(sin yaw, -cos yaw), left to right in the image. Inner corner (or line crossing) (i, j) lies at
``near_left + i * step * across + j * step * away``, ``step`` being ``square`` or ``spacing``.

.. code-block:: toml

    kind = "checkerboard"       # or "lines"
    inner_corners = [9, 7]      # inner corners across (left to right) and away from the camera
    square = 0.10               # metres
    near_left = [0.45, 0.40]    # ground position of the inner corner nearest the camera, furthest left
    yaw = 0.0                   # optional, rad
    # kind = "lines": spacing = 0.20, lines = [7, 9], line_width = 0.02 (optional)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np

from .._atomic import PathLike, write_atomic
from ..errors import ArgumentTypeError, ConfigError
from ..formats.toml_file import dumps_toml, load_toml, loads_toml

MAX_COUNT = 100
"""Most inner corners (lines) in one direction."""


class PatternKind(str, Enum):
    """What lies on the floor."""

    CHECKERBOARD = "checkerboard"
    """A board of alternating dark and light squares; its inner corners are the points."""
    LINES = "lines"
    """Dark lines on the floor at regular spacing (the paper's pattern); crossings are the points."""


# Keys each kind accepts (TOML names), and which of them are required.
_KEYS = {
    PatternKind.CHECKERBOARD: ({"kind", "inner_corners", "square", "near_left", "yaw"}, {"yaw"}),
    PatternKind.LINES: (
        {"kind", "spacing", "lines", "near_left", "yaw", "line_width"},
        {"yaw", "line_width"},
    ),
}


@dataclass(frozen=True)
class Pattern:
    """A calibration pattern lying on the floor, in the camera ground frame.

    Fields (validated on construction; build one with :meth:`checkerboard`, :meth:`lines` or
    :meth:`load`):

    - ``kind``: :class:`PatternKind`.
    - ``counts``: (across, away): inner corners (checkerboard, ``inner_corners``) or lines
      (``lines``: lines running away, counted across; lines running across, counted away).
      Each in 2..100.
    - ``step_m``: [m] side of a square (``square``) or distance between lines (``spacing``),
      in (0.001, 10].
    - ``near_left``: (x, y) [m], the inner corner / crossing nearest the camera, furthest left.
    - ``yaw``: [rad] rotation of the away axis from +x, counter-clockwise. Default 0.
    - ``line_width_m``: [m] width of the lines (``lines`` only), in (0, step / 2]. Default 0.02.

    >>> board = Pattern.from_toml('''
    ... kind = "checkerboard"
    ... inner_corners = [7, 5]
    ... square = 0.031
    ... near_left = [0.16, 0.093]
    ... ''')
    >>> board.counts, board.ground_of([0, 6], [0, 4]).round(3).tolist()
    ((7, 5), [[0.16, 0.093], [0.284, -0.093]])
    """

    kind: PatternKind
    counts: Tuple[int, int]
    step_m: float
    near_left: Tuple[float, float]
    yaw: float = 0.0
    line_width_m: Optional[float] = None

    def __post_init__(self) -> None:
        kind = self.kind
        if not isinstance(kind, PatternKind):
            try:
                kind = PatternKind(kind)
            except ValueError:
                raise ConfigError(
                    f"pattern: `kind` must be one of {[k.value for k in PatternKind]}, got {kind!r}"
                ) from None
            object.__setattr__(self, "kind", kind)
        name = "inner_corners" if kind is PatternKind.CHECKERBOARD else "lines"
        counts = tuple(int(n) for n in self.counts)
        if len(counts) != 2 or not all(2 <= n <= MAX_COUNT for n in counts):
            raise ConfigError(
                f"pattern: `{name}` must be two counts in 2..{MAX_COUNT}, got {counts}"
            )
        object.__setattr__(self, "counts", counts)
        step = "square" if kind is PatternKind.CHECKERBOARD else "spacing"
        if not (math.isfinite(self.step_m) and 1e-3 < self.step_m <= 10.0):
            raise ConfigError(f"pattern: `{step}` must be in (0.001, 10] m, got {self.step_m}")
        if not all(math.isfinite(c) for c in (*self.near_left, self.yaw)):
            raise ConfigError(
                f"pattern: `near_left` and `yaw` must be finite, got {self.near_left}, {self.yaw}"
            )
        object.__setattr__(self, "near_left", (float(self.near_left[0]), float(self.near_left[1])))
        if kind is PatternKind.LINES:
            w = 0.02 if self.line_width_m is None else float(self.line_width_m)
            if not (math.isfinite(w) and 0 < w <= self.step_m / 2):
                raise ConfigError(
                    f"pattern: `line_width` must be in (0, spacing / 2 = {self.step_m / 2}] m, got {w}"
                )
            object.__setattr__(self, "line_width_m", w)
        elif self.line_width_m is not None:
            raise ConfigError('pattern: `line_width` applies to kind = "lines" only')

    # --- construction -------------------------------------------------------------------
    @classmethod
    def checkerboard(
        cls,
        *,
        inner_corners: Tuple[int, int],
        square: float,
        near_left: Tuple[float, float],
        yaw: float = 0.0,
    ) -> Pattern:
        """A checkerboard of ``inner_corners`` (across, away) inner corners, squares of
        ``square`` [m], nearest-left inner corner at ``near_left`` (x, y) [m]."""
        return cls(PatternKind.CHECKERBOARD, tuple(inner_corners), float(square), near_left, yaw)

    @classmethod
    def lines(
        cls,
        *,
        lines: Tuple[int, int],
        spacing: float,
        near_left: Tuple[float, float],
        yaw: float = 0.0,
        line_width: float = 0.02,
    ) -> Pattern:
        """Dark lines ``spacing`` [m] apart: ``lines`` = (running away, running across); the
        nearest-left crossing at ``near_left`` (x, y) [m]."""
        return cls(PatternKind.LINES, tuple(lines), float(spacing), near_left, yaw, line_width)

    @classmethod
    def from_dict(cls, d: Dict[str, Any], *, source: str = "pattern") -> Pattern:
        """From the ``pattern.toml`` keys; unknown, missing or ill-typed keys raise
        :class:`floorscan.ConfigError` naming the key."""
        if not isinstance(d, dict):
            raise ConfigError(f"{source}: a pattern must be a table of keys")
        if "kind" not in d:
            raise ConfigError(f'{source}: missing key `kind` ("checkerboard" or "lines")')
        try:
            kind = PatternKind(d["kind"])
        except (ValueError, TypeError):
            raise ConfigError(
                f'{source}: `kind` must be "checkerboard" or "lines", got {d["kind"]!r}'
            ) from None
        known, optional = _KEYS[kind]
        for k in d:
            if k not in known:
                raise ConfigError(
                    f'{source}: unknown key `{k}` for kind = "{kind.value}" '
                    f"(known: {', '.join(sorted(known))})"
                )
        for k in sorted(known - optional - set(d)):
            raise ConfigError(f"{source}: missing key `{k}`")
        near_left = _pair(d, "near_left", float, source)
        yaw = _number(d, "yaw", source) if "yaw" in d else 0.0
        try:
            if kind is PatternKind.CHECKERBOARD:
                return cls(
                    kind,
                    _pair(d, "inner_corners", int, source),
                    _number(d, "square", source),
                    near_left,
                    yaw,
                )
            width = _number(d, "line_width", source) if "line_width" in d else None
            return cls(
                kind,
                _pair(d, "lines", int, source),
                _number(d, "spacing", source),
                near_left,
                yaw,
                width,
            )
        except ConfigError as e:
            raise ConfigError(f"{source}: {str(e).removeprefix('pattern: ')}") from None

    @classmethod
    def load(cls, path: PathLike) -> Pattern:
        """Reads a ``pattern.toml`` file."""
        return cls.from_dict(load_toml(Path(path)), source=str(path))

    @classmethod
    def from_toml(cls, text: str, *, source: str = "pattern") -> Pattern:
        return cls.from_dict(loads_toml(text, source=source), source=source)

    @classmethod
    def resolve(cls, pattern: Union[Pattern, PathLike]) -> Pattern:
        """A :class:`Pattern` as is, or one read from a TOML file path."""
        if isinstance(pattern, Pattern):
            return pattern
        if isinstance(pattern, (str, Path)) or hasattr(pattern, "__fspath__"):
            return cls.load(pattern)
        raise ArgumentTypeError(
            f"pattern must be a Pattern or a path, got {type(pattern).__name__}"
        )

    # --- geometry -----------------------------------------------------------------------
    @property
    def point_count(self) -> int:
        return self.counts[0] * self.counts[1]

    @property
    def extent_m(self) -> float:
        """How far the pattern reaches beyond its outermost points [m]: a checkerboard's
        outer squares (one square), a line grid's overhang (half a spacing)."""
        return self.step_m if self.kind is PatternKind.CHECKERBOARD else 0.5 * self.step_m

    def axes(self) -> Tuple[np.ndarray, np.ndarray]:
        """(across, away) unit vectors in the ground frame."""
        s, c = math.sin(self.yaw), math.cos(self.yaw)
        return np.array([s, -c]), np.array([c, s])

    def ground_of(self, i, j) -> np.ndarray:
        """Ground points [m] of (possibly fractional) pattern coordinates (i across, j away):
        array of shape ``broadcast(i, j).shape + (2,)``."""
        across, away = self.axes()
        i = np.asarray(i, dtype=np.float64)[..., None]
        j = np.asarray(j, dtype=np.float64)[..., None]
        return np.asarray(self.near_left) + self.step_m * (i * across + j * away)

    def points(self) -> np.ndarray:
        """All inner corners (crossings), (M, 2) [m]: row by row away from the camera (j),
        left to right within a row (i)."""
        j, i = np.mgrid[0 : self.counts[1], 0 : self.counts[0]]
        return self.ground_of(i.ravel(), j.ravel())

    # --- files --------------------------------------------------------------------------
    def to_dict(self) -> Dict[str, Any]:
        """The ``pattern.toml`` keys."""
        d: Dict[str, Any] = {"kind": self.kind.value}
        if self.kind is PatternKind.CHECKERBOARD:
            d["inner_corners"] = list(self.counts)
            d["square"] = self.step_m
        else:
            d["lines"] = list(self.counts)
            d["spacing"] = self.step_m
            d["line_width"] = self.line_width_m
        d["near_left"] = list(self.near_left)
        d["yaw"] = self.yaw
        return d

    def to_toml(self) -> str:
        return "# floorscan calibration pattern (docs/calibration.md)\n" + dumps_toml(
            self.to_dict()
        )

    def save(self, path: PathLike) -> Path:
        return write_atomic(path, self.to_toml())


def _number(d: Dict[str, Any], key: str, source: str) -> float:
    v = d[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ConfigError(f"{source}: `{key}` must be a finite number, got {v!r}")
    return float(v)


def _pair(d: Dict[str, Any], key: str, typ: type, source: str) -> tuple:
    v = d[key]
    what = "integers" if typ is int else "numbers"
    ok = isinstance(v, list) and len(v) == 2
    if ok:
        for x in v:
            if isinstance(x, bool) or not isinstance(x, (int,) if typ is int else (int, float)):
                ok = False
            elif typ is float and not math.isfinite(x):
                ok = False
    if not ok:
        raise ConfigError(f"{source}: `{key}` must be a list of two {what}, got {v!r}")
    return (typ(v[0]), typ(v[1]))
