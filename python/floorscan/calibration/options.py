"""Options of a calibration (one validated structure; the ``[calibration]`` table of the
configuration file holds ``spacing_px`` and ``extrapolate``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

from ..errors import OptionError


@dataclass(frozen=True)
class CalibrationOptions:
    """How a ground table is built from a pattern image.

    - ``spacing_px``: table node spacing [px], 1..64. Default 8.
    - ``extrapolate``: trust the fitted model beyond the margin around the pattern (still only
      below the horizon, where the model is valid and within ``max_range_m``). Default False:
      the table says "no ground" outside the calibrated region, as the paper does.
    - ``margin_m``: [m] how far beyond the detected points' outline the table still claims
      ground without extrapolating, in [0, 10]. Default None: as far as the pattern itself
      reaches (one square beyond a checkerboard's inner corners, half a spacing beyond the
      outermost crossings of a line grid).
    - ``near_field``: count the floor between the camera and the pattern as calibrated (the
      region is the outline of the pattern's points and the camera's ground origin, plus the
      margin), so the bottom rows of the image, where the range sensor starts each column, have
      ground although the pattern lies further out. Rays there are steep and interpolate the
      calibrated ones in image radius; measured on the simulator within 0.8 cm of the truth for
      its default patterns. Default True; False keeps the pattern's own outline only.
    - ``max_range_m``: [m] no ground beyond this distance from the camera, in (0, 1000].
      Default 10.
    - ``leave_one_out``: refit without each point in turn to report its prediction error
      (exact, about 63 small refits); False reports the linearised estimate instead. Default
      True.
    """

    spacing_px: int = 8
    extrapolate: bool = False
    margin_m: Optional[float] = None
    near_field: bool = True
    max_range_m: float = 10.0
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
        if not isinstance(self.extrapolate, bool):
            raise OptionError(
                f"invalid option `extrapolate`: must be true or false, got {self.extrapolate!r}"
            )
        if not isinstance(self.near_field, bool):
            raise OptionError(
                f"invalid option `near_field`: must be true or false, got {self.near_field!r}"
            )
        if self.margin_m is not None and not (
            isinstance(self.margin_m, (int, float)) and 0 <= self.margin_m <= 10
        ):
            raise OptionError(
                f"invalid option `margin_m`: must be in [0, 10] m, got {self.margin_m!r}"
            )
        if not (
            isinstance(self.max_range_m, (int, float))
            and math.isfinite(self.max_range_m)
            and 0 < self.max_range_m <= 1000
        ):
            raise OptionError(
                f"invalid option `max_range_m`: must be in (0, 1000] m, got {self.max_range_m!r}"
            )
