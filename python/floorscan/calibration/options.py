"""Options of a calibration (one validated structure; the ``[calibration]`` table of the
configuration file holds these fields)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import Optional, Tuple

from ..errors import OptionError
from .lens_family import DEFAULT_FAMILIES, FAMILIES


class Coverage(str, Enum):
    """Which table nodes claim ground.

    - ``trusted`` (default): wherever the fitted camera model sees floor within
      ``max_range_m`` and its predicted error is at most ``max_error_fraction`` of the range.
    - ``pattern``: only around the pattern (the paper's calibrated region: the points found,
      the floor between them and the camera with ``near_field``, plus ``margin_m``).
    - ``all``: wherever the model sees floor within ``max_range_m`` (the old
      ``extrapolate``), whatever its predicted error.
    """

    TRUSTED = "trusted"
    PATTERN = "pattern"
    ALL = "all"


@dataclass(frozen=True)
class CalibrationOptions:
    """How a ground table is built from pattern images.

    - ``spacing_px``: table node spacing [px], 1..64. Default 4 (at 8 px the bilinear
      interpolation alone is off by up to 2 cm at 2-3 m on a 640 x 480 camera 0.25 m up).
    - ``coverage``: :class:`Coverage` (``"trusted"``, ``"pattern"``, ``"all"``). Default
      ``"trusted"``. ``extrapolate = True`` is the older spelling of ``"all"``.
    - ``max_error_fraction``: with ``trusted``, the largest predicted floor error a node may
      have, as a fraction of its range, in (0, 1]. Default 0.03 (3 cm at 1 m, 9 cm at 3 m:
      about the floor one pixel row covers at 3 m for a 640 x 480 camera 0.3 m up).
    - ``min_error_m``: [m] with ``trusted``, a node is kept whatever its range if its
      predicted error is at most this, in [0, 1]. Default 0.04 (one cell of the default 4 cm
      map: a reading that far off still marks its cell or the next): the floor near the
      robot, where 3 % of the range is less than a cell, including the bottom corners of a
      wide lens, which a one-board calibration can tell only to a few centimetres and where
      obstacles beside the robot stand (0.02 before: EVALUATION.md, "Legs at default
      settings").
    - ``max_range_m``: [m] no ground beyond this distance from the camera, in (0, 1000].
      Default 3.0, the range sensor's default maximum range.
    - ``horizon_margin_rad``: [rad] no ground on rays less than this far below the horizon,
      in [0, 0.5]. Default 0.02 (about a degree).
    - ``families``: lens families tried (names of :data:`lens_family.FAMILIES`). Default all.
    - ``margin_m``, ``near_field``: the calibrated region of ``coverage = "pattern"``: [m]
      how far beyond the points' outline (default: the pattern's own reach: a square beyond a
      checkerboard's inner corners, half a spacing beyond a line grid's crossings), and
      whether the floor between the camera and the pattern counts (default True).
    - ``leave_one_out``: refit without each point in turn for its held-out error (default
      True; False reports the residual instead).
    """

    spacing_px: int = 4
    coverage: Coverage = Coverage.TRUSTED
    max_error_fraction: float = 0.03
    min_error_m: float = 0.04
    max_range_m: float = 3.0
    horizon_margin_rad: float = 0.02
    families: Tuple[str, ...] = DEFAULT_FAMILIES
    margin_m: Optional[float] = None
    near_field: bool = True
    leave_one_out: bool = True

    def __post_init__(self) -> None:
        if isinstance(self.spacing_px, bool) or not isinstance(self.spacing_px, int):
            raise OptionError(
                f"invalid option `spacing_px`: must be an integer, got {self.spacing_px!r}"
            )
        if not 1 <= self.spacing_px <= 64:
            raise OptionError(
                f"invalid option `spacing_px`: must be in 1..64, got {self.spacing_px}"
            )
        try:
            object.__setattr__(self, "coverage", Coverage(self.coverage))
        except ValueError:
            raise OptionError(
                "invalid option `coverage`: expected one of "
                f"{[c.value for c in Coverage]}, got {self.coverage!r}"
            ) from None
        _number("max_error_fraction", self.max_error_fraction, 0.0, 1.0, low_open=True)
        _number("min_error_m", self.min_error_m, 0.0, 1.0)
        _number("max_range_m", self.max_range_m, 0.0, 1000.0, low_open=True)
        _number("horizon_margin_rad", self.horizon_margin_rad, 0.0, 0.5)
        families = (self.families,) if isinstance(self.families, str) else tuple(self.families)
        unknown = [f for f in families if f not in FAMILIES]
        if unknown or not families:
            raise OptionError(
                f"invalid option `families`: unknown {unknown or 'empty list'}; "
                f"known: {sorted(FAMILIES)}"
            )
        object.__setattr__(self, "families", families)
        if not isinstance(self.near_field, bool):
            raise OptionError(
                f"invalid option `near_field`: must be true or false, got {self.near_field!r}"
            )
        if self.margin_m is not None:
            _number("margin_m", self.margin_m, 0.0, 10.0)


def _number(name: str, value, low: float, high: float, *, low_open: bool = False) -> None:
    ok = (
        isinstance(value, (int, float))
        and not isinstance(value, bool)
        and math.isfinite(value)
        and (low < value if low_open else low <= value)
        and value <= high
    )
    if not ok:
        lo = "(" if low_open else "["
        raise OptionError(f"invalid option `{name}`: must be in {lo}{low}, {high}], got {value!r}")
