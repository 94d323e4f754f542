"""The visual range sensor: images in, scans out (paper III).

Each sampled column is scanned from the bottom with the incremental box edge filter; the first
edge whose response exceeds the threshold is the floor boundary, and the ground table turns it
into a point in the camera ground frame.
"""

from __future__ import annotations

import json
import math
from typing import Any, Dict, Optional, Sequence, Union

import numpy as np

from .. import _native
from ..errors import ArgumentTypeError, ImageError, OptionError
from ..formats.image_io import as_grey
from .ground_table import GroundTable
from .scan import Scan

REFINEMENTS = {"subpixel": "sub_pixel", "peak": "peak", "none": "first_crossing"}
"""Accepted ``refine`` values: ``"subpixel"`` (default), ``"peak"``, ``"none"`` (the paper)."""


U16_PER_U8 = 257.0
"""65535 / 255: one 8-bit intensity unit in a uint16 image (the threshold's scale there)."""


class VisualRanger:
    """Turns greyscale images into :class:`~floorscan.Scan` s.

    Parameters (keyword-only after ``table``):
        table: the :class:`GroundTable` of the camera (fixes the image size).
        columns: number of evenly spaced columns, or an explicit sequence of image columns
            [px]. Default 64.
        half_width: half-width d of the box filter [px], >= 1. Default 4.
        threshold: edge threshold on the difference of the two window means, in 8-bit
            intensity units (0-255), finite, >= 0. Default 10. A uint16 image is compared at
            ``threshold * 257`` (65535 / 255), so one frame saved at either depth gives the
            same scan.
        refine: ``"subpixel"`` (default), ``"peak"``, or ``"none"`` (the paper's first
            crossing; ``False`` is accepted too).
        bottom_margin: rows skipped at the bottom of every column (bumper, dead border row)
            [px]. Default 2.
        mask: optional (H, W) boolean array, True where the image shows floor the robot may
            see; each column starts at its lowest True pixel. Overrides ``bottom_margin``.
        max_range_m: farthest ground range scanned [m], default 3 (beyond it a 320x240
            wide-angle camera sees more than 10 cm of floor per pixel row); ``None`` scans as
            far as the table has ground.

    >>> from floorscan import GroundTable, Lens, CameraMount, VisualRanger
    >>> table = GroundTable.from_camera(Lens.equidistant(f=140, cx=159.5, cy=119.5),
    ...                                 CameraMount(height_m=0.4, tilt_rad=0.6),
    ...                                 image_width=320, image_height=240)
    >>> ranger = VisualRanger(table, columns=16)
    >>> import numpy as np
    >>> image = np.full((240, 320), 90, np.uint8); image[:150] = 200   # boundary at row 150
    >>> scan = ranger.scan(image, timestamp=0.0)
    >>> sorted(set(scan.status))
    ['boundary']
    >>> float(scan.rows[0])
    149.5
    """

    def __init__(
        self,
        table: GroundTable,
        *,
        columns: Union[int, Sequence[int]] = 64,
        half_width: int = 4,
        threshold: float = 10.0,
        refine: Union[str, bool] = "subpixel",
        bottom_margin: int = 2,
        mask: Optional[np.ndarray] = None,
        max_range_m: Optional[float] = 3.0,
    ) -> None:
        if not isinstance(table, GroundTable):
            raise ArgumentTypeError(
                f"table must be a floorscan.GroundTable, got {type(table).__name__}"
            )
        self._table = table
        options = build_ranger_options(
            image_width=table.image_width,
            image_height=table.image_height,
            columns=columns,
            half_width=half_width,
            threshold=threshold,
            refine=refine,
            bottom_margin=bottom_margin,
            mask=mask,
            max_range_m=max_range_m,
        )
        self._options = options
        self._native = _native.VisualRanger(table._native, json.dumps(options))
        self._native16: Optional[object] = None

    @property
    def table(self) -> GroundTable:
        return self._table

    @property
    def columns(self) -> np.ndarray:
        """Sampled image columns [px], in output order."""
        return self._native.columns

    @property
    def options(self) -> Dict[str, Any]:
        """The validated options (the ``[ranger]`` config table's native form)."""
        return json.loads(self._native.options_json)

    def scan(self, image: np.ndarray, *, timestamp: float = 0.0) -> Scan:
        """Scans one (H, W) uint8/uint16 image (colour is converted to grey). The GIL is
        released while the columns are scanned."""
        grey = as_grey(image)
        if grey.shape != (self._table.image_height, self._table.image_width):
            raise ImageError(
                f"image is {grey.shape[1]} x {grey.shape[0]} (W x H) but the calibration table is "
                f"for {self._table.image_width} x {self._table.image_height}"
            )
        try:
            t = float(timestamp)
        except (TypeError, ValueError):
            raise OptionError(
                f"invalid option `timestamp`: must be a number [s], got {timestamp!r}"
            ) from None
        if not math.isfinite(t):
            raise OptionError(f"invalid option `timestamp`: must be finite, got {timestamp}")
        if grey.dtype == np.uint16:
            if self._native16 is None:
                options = dict(self._options, threshold=self._options["threshold"] * U16_PER_U8)
                self._native16 = _native.VisualRanger(self._table._native, json.dumps(options))
            return Scan(self._native16.scan(grey, t))
        return Scan(self._native.scan(grey, t))


def build_ranger_options(
    *,
    image_width: int,
    image_height: int,
    columns: Union[int, Sequence[int]],
    half_width: int,
    threshold: float,
    refine: Union[str, bool],
    bottom_margin: int,
    mask: Optional[np.ndarray],
    max_range_m: Optional[float],
) -> Dict[str, Any]:
    """Checks the ranger options' types and returns the core's serde form."""
    if isinstance(half_width, bool) or not isinstance(half_width, (int, np.integer)):
        raise OptionError(f"invalid option `half_width`: must be an integer, got {half_width!r}")
    if half_width < 1:
        raise OptionError(f"invalid option `half_width`: must be >= 1, got {half_width}")
    try:
        threshold = float(threshold)
    except (TypeError, ValueError):
        raise OptionError(
            f"invalid option `threshold`: must be a number, got {threshold!r}"
        ) from None
    if not math.isfinite(threshold) or threshold < 0:
        raise OptionError(f"invalid option `threshold`: must be finite and >= 0, got {threshold}")
    if refine is False:
        refine = "none"
    elif refine is True:
        refine = "subpixel"
    if refine not in REFINEMENTS:
        raise OptionError(
            f"invalid option `refine`: expected one of {sorted(REFINEMENTS)}, got {refine!r}"
        )
    if isinstance(columns, (int, np.integer)) and not isinstance(columns, bool):
        if not 1 <= columns <= image_width:
            raise OptionError(
                f"invalid option `columns`: count must be in 1..={image_width}, got {columns}"
            )
        column_sel: Dict[str, Any] = {"count": int(columns)}
    else:
        cols = np.asarray(columns)
        if cols.ndim != 1 or cols.size == 0 or cols.dtype.kind not in "iu":
            raise OptionError(
                "invalid option `columns`: give a count or a non-empty list of integers"
            )
        bad = cols[(cols < 0) | (cols >= image_width)]
        if bad.size:
            raise OptionError(
                f"invalid option `columns`: column {int(bad[0])} is outside the image (width {image_width})"
            )
        column_sel = {"explicit": [int(c) for c in cols]}
    if mask is not None:
        start: Dict[str, Any] = {
            "per_column": start_rows_from_mask(mask, image_width, image_height)
        }
    else:
        if (
            isinstance(bottom_margin, bool)
            or not isinstance(bottom_margin, (int, np.integer))
            or bottom_margin < 0
        ):
            raise OptionError(
                f"invalid option `bottom_margin`: must be an integer >= 0, got {bottom_margin!r}"
            )
        if bottom_margin >= image_height:
            raise OptionError(
                f"invalid option `bottom_margin`: {bottom_margin} rows leaves nothing of a {image_height}-row image"
            )
        start = {"bottom_margin": int(bottom_margin)}
    if max_range_m is not None and float(max_range_m) == math.inf:
        max_range_m = None  # no limit
    if max_range_m is not None:
        max_range_m = float(max_range_m)
        if not (math.isfinite(max_range_m) and max_range_m > 0):
            raise OptionError(
                f"invalid option `max_range_m`: must be finite and > 0, got {max_range_m}"
            )
    return {
        "half_width_px": int(half_width),
        "threshold": threshold,
        "refinement": REFINEMENTS[refine],
        "columns": column_sel,
        "start": start,
        "max_range_m": max_range_m,
    }


def start_rows_from_mask(mask: np.ndarray, image_width: int, image_height: int) -> list:
    """Per image column, the lowest row where ``mask`` is True (row 0 if none: such a column
    sees no floor and reads as ``invalid``)."""
    m = np.asarray(mask)
    if m.shape != (image_height, image_width):
        raise OptionError(
            f"invalid option `mask`: shape must be (H, W) = ({image_height}, {image_width}), got {m.shape}"
        )
    m = m.astype(bool)
    flipped = m[::-1]
    any_true = flipped.any(axis=0)
    lowest = image_height - 1 - flipped.argmax(axis=0)
    return [int(r) if ok else 0 for r, ok in zip(lowest, any_true)]
