"""The appearance range sensor: ranging that does not rely on the texture assumption (the
paper's future work; Ulrich & Nourbakhsh 2000, Lorigo et al. 1997).

A model of what the floor looks like (histograms of colour and local texture) is learned from a
band of floor just in front of the robot (the bottom of the image) and blended over frames;
per sampled column, the lowest row of the first run of rows that do not look like floor is the
boundary, looked up in the ground table like the edge ranger's (same statuses). Colour images
are first-class; greyscale works too (every channel the same).
"""

from __future__ import annotations

import json
import math
from typing import Any, Dict, Optional, Sequence, Union

import numpy as np

from .. import _native
from ..errors import ImageError, ImageTypeError, OptionError
from .ground_table import GroundTable
from .ranger import build_ranger_options
from .scan import Scan

FEATURES = {"colour": "colour", "colour_texture": "colour_and_texture"}
"""Accepted ``features`` values: ``"colour_texture"`` (default) or ``"colour"``."""


class AppearanceRanger:
    """Turns colour (or grey) images into :class:`~floorscan.Scan` s by floor appearance.

    Parameters (keyword-only after ``table``):
        table: the :class:`GroundTable` of the camera (fixes the image size).
        columns: number of evenly spaced columns, or explicit image columns [px]. Default 64.
        bottom_margin: rows skipped at the bottom of every column [px]. Default 2.
        mask: optional (H, W) boolean floor-visibility mask (overrides ``bottom_margin``).
        max_range_m: farthest ground range scanned [m], default 3; ``None``: no limit.
        reference_fraction: height of the reference band of floor above each column's start,
            as a share of the image height, in (0, 0.5]. Default 0.1.
        features: ``"colour_texture"`` (default) or ``"colour"``.
        min_floor_share: a pixel looks like floor when at least this share of the reference
            lies within one histogram bin of it, in (0, 1). Default 0.003.
        intensity_reach: how far in intensity (bins of 16 grey levels) a pixel may lie from the
            reference and still match it, 1..15. Default 1.
        patch_half_width: half-width of the patch classified around each column [px]. Default 2.
        min_run: rows of not-floor in a run that make a boundary, >= 1. Default 3.
        adaptation_rate: weight of the newest frame's reference in the model, in (0, 1].
            Default 0.5.

    >>> from floorscan import GroundTable, Lens, CameraMount, AppearanceRanger
    >>> table = GroundTable.from_camera(Lens.equidistant(f=140, cx=159.5, cy=119.5),
    ...                                 CameraMount(height_m=0.4, tilt_rad=0.6),
    ...                                 image_width=320, image_height=240)
    >>> ranger = AppearanceRanger(table, columns=16)
    >>> import numpy as np
    >>> image = np.zeros((240, 320, 3), np.uint8); image[150:] = (120, 110, 90)  # floor
    >>> image[:150] = (30, 60, 160)                                             # a blue wall
    >>> scan = ranger.scan(image, timestamp=0.0)
    >>> sorted(set(scan.status)), float(scan.rows[0])
    (['boundary'], 149.5)
    """

    def __init__(
        self,
        table: GroundTable,
        *,
        columns: Union[int, Sequence[int]] = 64,
        bottom_margin: int = 2,
        mask: Optional[np.ndarray] = None,
        max_range_m: Optional[float] = 3.0,
        reference_fraction: float = 0.1,
        features: str = "colour_texture",
        min_floor_share: float = 0.003,
        intensity_reach: int = 1,
        patch_half_width: int = 2,
        min_run: int = 3,
        adaptation_rate: float = 0.5,
    ) -> None:
        if not isinstance(table, GroundTable):
            raise TypeError(f"table must be a floorscan.GroundTable, got {type(table).__name__}")
        self._table = table
        options = build_appearance_options(
            image_width=table.image_width,
            image_height=table.image_height,
            columns=columns,
            bottom_margin=bottom_margin,
            mask=mask,
            max_range_m=max_range_m,
            reference_fraction=reference_fraction,
            features=features,
            min_floor_share=min_floor_share,
            intensity_reach=intensity_reach,
            patch_half_width=patch_half_width,
            min_run=min_run,
            adaptation_rate=adaptation_rate,
        )
        self._native = _native.AppearanceRanger(table._native, json.dumps(options))

    @property
    def table(self) -> GroundTable:
        return self._table

    @property
    def columns(self) -> np.ndarray:
        """Sampled image columns [px], in output order."""
        return self._native.columns

    @property
    def options(self) -> Dict[str, Any]:
        """The validated options (the core's serde form)."""
        return json.loads(self._native.options_json)

    @property
    def frames_learned(self) -> int:
        """Frames folded into the floor model since it was created or reset."""
        return self._native.frames_learned

    def reset_model(self) -> None:
        """Forgets the learned floor (the next frame's reference band is the whole model)."""
        self._native.reset_model()

    def scan(self, image: np.ndarray, *, timestamp: float = 0.0) -> Scan:
        """Learns from the frame's reference band, then scans it. ``image``: (H, W, 3) RGB or
        (H, W) grey, uint8 or uint16 ((H, W, 4) drops alpha). The GIL is released."""
        arr = as_rgb_or_grey(image)
        if arr.shape[:2] != (self._table.image_height, self._table.image_width):
            raise ImageError(
                f"image is {arr.shape[1]} x {arr.shape[0]} (W x H) but the calibration table is "
                f"for {self._table.image_width} x {self._table.image_height}"
            )
        t = float(timestamp)
        if not math.isfinite(t):
            raise OptionError(f"invalid option `timestamp`: must be finite, got {timestamp}")
        return Scan(self._native.scan(arr, t))


def as_rgb_or_grey(image) -> np.ndarray:
    """A C-contiguous (H, W, 3) or a (H, W) uint8/uint16 array for the native ranger."""
    if not isinstance(image, np.ndarray):
        raise ImageTypeError(f"image must be a numpy array, got {type(image).__name__}")
    if image.dtype not in (np.uint8, np.uint16):
        raise ImageTypeError(f"image dtype must be uint8 or uint16, got {image.dtype}")
    if image.ndim == 3 and image.shape[2] in (3, 4):
        return np.ascontiguousarray(image[..., :3])
    if image.ndim == 3 and image.shape[2] == 1:
        image = image[..., 0]
    if image.ndim != 2:
        raise ImageError(
            f"image must be (H, W) greyscale or (H, W, 3) colour, got shape {image.shape}"
        )
    if image.shape[0] == 0 or image.shape[1] == 0:
        raise ImageError(f"image is empty: shape {image.shape} (H, W)")
    return image


def _number(name: str, value, lo: float, hi: float, *, lo_open: bool, hi_open: bool) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise OptionError(f"invalid option `{name}`: must be a number, got {value!r}") from None
    ok = math.isfinite(v) and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        rng = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise OptionError(f"invalid option `{name}`: must be in {rng}, got {value}")
    return v


def _count(name: str, value, lo: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
        raise OptionError(f"invalid option `{name}`: must be an integer >= {lo}, got {value!r}")
    return int(value)


def build_appearance_options(
    *,
    image_width: int,
    image_height: int,
    columns: Union[int, Sequence[int]] = 64,
    bottom_margin: int = 2,
    mask: Optional[np.ndarray] = None,
    max_range_m: Optional[float] = 3.0,
    reference_fraction: float = 0.1,
    features: str = "colour_texture",
    min_floor_share: float = 0.003,
    intensity_reach: int = 1,
    patch_half_width: int = 2,
    min_run: int = 3,
    adaptation_rate: float = 0.5,
) -> Dict[str, Any]:
    """Checks the appearance ranger's options and returns the core's serde form."""
    shared = build_ranger_options(
        image_width=image_width,
        image_height=image_height,
        columns=columns,
        half_width=1,
        threshold=0.0,
        refine="none",
        bottom_margin=bottom_margin,
        mask=mask,
        max_range_m=max_range_m,
    )
    if features not in FEATURES:
        raise OptionError(
            f"invalid option `features`: expected one of {sorted(FEATURES)}, got {features!r}"
        )
    return {
        "columns": shared["columns"],
        "start": shared["start"],
        "max_range_m": shared["max_range_m"],
        "reference_fraction": _number(
            "reference_fraction", reference_fraction, 0, 0.5, lo_open=True, hi_open=False
        ),
        "features": FEATURES[features],
        "min_floor_share": _number(
            "min_floor_share", min_floor_share, 0, 1, lo_open=True, hi_open=True
        ),
        "intensity_reach_bins": _count("intensity_reach", intensity_reach, 1),
        "patch_half_width_px": _count("patch_half_width", patch_half_width, 0),
        "min_run_px": _count("min_run", min_run, 1),
        "adaptation_rate": _number(
            "adaptation_rate", adaptation_rate, 0, 1, lo_open=True, hi_open=False
        ),
    }
