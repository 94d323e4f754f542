"""The calibration scene: the robot's camera looking at a pattern on the floor (a checkerboard,
or the paper's dark lines at 20 cm), and its description in the public ``pattern.toml`` format
(docs/dataset-format.md), in the camera ground frame (x forward, y left, metres)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Tuple

import numpy as np

from .._atomic import PathLike, write_atomic
from .._native import sim as _native
from ..errors import OptionError
from .camera import Camera

PATTERN_KINDS = ("checkerboard", "lines")


@dataclass(frozen=True)
class CalibrationPattern:
    """A floor pattern in the camera ground frame.

    - ``kind``: ``"checkerboard"`` or ``"lines"``.
    - ``near_left`` (x, y) [m]: the inner corner (crossing) nearest the camera, furthest left.
    - ``yaw`` [rad]: rotation of the "away" axis from +x (CCW); "across" is -y rotated by yaw.
    - checkerboard: ``inner_corners`` (across, away), ``square`` [m].
    - lines: ``spacing`` [m], ``lines`` (running away, running across), ``line_width`` [m].
    """

    kind: str
    near_left: Tuple[float, float]
    yaw: float = 0.0
    inner_corners: Tuple[int, int] = (9, 7)
    square: float = 0.10
    spacing: float = 0.20
    lines: Tuple[int, int] = (7, 9)
    line_width: float = 0.02

    def __post_init__(self) -> None:
        if self.kind not in PATTERN_KINDS:
            raise OptionError(
                f"invalid option `kind`: expected one of {PATTERN_KINDS}, got {self.kind!r}"
            )
        _native.validate_pattern(self._json())

    @classmethod
    def default_for(cls, camera: Camera, *, kind: str = "checkerboard") -> CalibrationPattern:
        """The default pattern of ``kind`` placed in front of ``camera``: a 9 x 7 inner-corner
        checkerboard of 10 cm squares, or 7 x 9 lines 2 cm wide at 20 cm; centred across the
        view, as near as it fits entirely in the image. A checkerboard whose rows would be
        flattened there (a camera low over the floor: a row step under 7 px and under 0.4 of
        the squares' width) shrinks to the largest of 7, 5, 3.5 and 2.5 cm squares that is
        legible, or when none is to the size whose rows lie widest apart
        (docs/simulator.md)."""
        if kind not in PATTERN_KINDS:
            raise OptionError(
                f"invalid option `kind`: expected one of {PATTERN_KINDS}, got {kind!r}"
            )
        d = json.loads(_native.sim_default_pattern(camera._native, kind))
        return cls._from_spec(d)

    @classmethod
    def _from_spec(cls, d: dict) -> CalibrationPattern:
        return cls(
            kind=d["kind"],
            near_left=(d["near_left"]["x"], d["near_left"]["y"]),
            yaw=d["yaw"],
            inner_corners=tuple(d["inner_corners"]),
            square=d["square_m"],
            spacing=d["spacing_m"],
            lines=tuple(d["lines"]),
            line_width=d["line_width_m"],
        )

    def _json(self) -> str:
        return json.dumps(
            {
                "kind": self.kind,
                "near_left": {"x": float(self.near_left[0]), "y": float(self.near_left[1])},
                "yaw": float(self.yaw),
                "inner_corners": [int(n) for n in self.inner_corners],
                "square_m": float(self.square),
                "spacing_m": float(self.spacing),
                "lines": [int(n) for n in self.lines],
                "line_width_m": float(self.line_width),
            }
        )

    def points(self) -> np.ndarray:
        """Inner corners (checkerboard) or crossings (lines), (M, 2) [m], camera ground frame:
        row by row away from the camera, left to right within a row."""
        return _native.sim_pattern_points(self._json())

    def to_toml(self) -> str:
        """The ``pattern.toml`` text."""
        x, y = self.near_left
        head = [
            "# Floor calibration pattern (floorscan dataset format, docs/dataset-format.md).",
            "# Camera ground frame: x forward, y left, metres; rows away from the camera.",
            f'kind = "{self.kind}"',
        ]
        if self.kind == "checkerboard":
            body = [
                f"inner_corners = [{self.inner_corners[0]}, {self.inner_corners[1]}]"
                "   # across (left to right in the image), away from the camera",
                f"square = {self.square!r}   # m",
            ]
        else:
            body = [
                f"spacing = {self.spacing!r}   # m between lines",
                f"lines = [{self.lines[0]}, {self.lines[1]}]"
                "   # running away from the camera (counted across), running across (counted away)",
                f"line_width = {self.line_width!r}   # m",
            ]
        tail = [
            f"near_left = [{_num(x)}, {_num(y)}]   # nearest-left inner corner / crossing, m",
            f"yaw = {_num(self.yaw)}   # rad, rotation of the away axis from +x (CCW)",
        ]
        return "\n".join(head + body + tail) + "\n"

    def save(self, path: PathLike) -> Path:
        return write_atomic(path, self.to_toml())


def _num(v: float) -> str:
    r = round(float(v), 9)
    return repr(0.0 if r == 0 else r) if math.isfinite(r) else "nan"


def render_calibration(
    camera: Camera, pattern: CalibrationPattern = None, *, kind: str = "checkerboard", seed: int = 0
) -> Tuple[np.ndarray, CalibrationPattern]:
    """Renders the robot's camera looking at a floor pattern (``pattern``, or the default of
    ``kind`` for this camera) on carpet. Returns the (H, W) uint8 image and the pattern."""
    if pattern is None:
        pattern = CalibrationPattern.default_for(camera, kind=kind)
    image, _labels = _native.sim_render_calibration(camera._native, pattern._json(), int(seed))
    return image, pattern
