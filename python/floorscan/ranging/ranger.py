"""The visual range sensor: images in, scans out (paper III).

Each sampled column is scanned from the bottom with the incremental box edge filter; the first
edge whose response exceeds the threshold is the floor boundary, and the ground table turns it
into a point in the camera ground frame.
"""

from __future__ import annotations

import enum
import math
from typing import Any, Dict, Optional

import numpy as np

from .._native import ranging as _native
from ..errors import ArgumentTypeError, ImageError, OptionError
from ..formats.image_io import as_grey
from ..options import in_user_words, plain
from .ground_table import GroundTable
from .scan import Scan

Refinement = enum.Enum(
    "Refinement",
    {
        v["const"].upper(): v["const"]
        for v in _native.ranger_options_schema()["$defs"]["Refinement"]["oneOf"]
    },
    type=str,
)
Refinement.__doc__ = """How the boundary row is placed (floorscan-core's ``Refinement``, built from
its schema): the values are the ``refinement`` option's spellings.

>>> [r.value for r in Refinement]
['first_crossing', 'peak', 'sub_pixel', 'step']
"""


U16_PER_U8 = 257.0
"""65535 / 255: one 8-bit intensity unit in a uint16 image (the threshold's scale there)."""


class VisualRanger:
    """Turns greyscale images into :class:`~floorscan.Scan` s.

    Parameters (keyword-only after ``table``):
        table: the :class:`GroundTable` of the camera (fixes the image size).
        mask: optional (H, W) boolean array, True where the image shows floor the robot may
            see; each column starts at its lowest True pixel (sets ``start``).
        **options: any field of the core's ``RangerOptions`` (its serde form; the others take
            their defaults, ``floorscan.options.defaults("ranger")``): ``half_width_px``,
            ``threshold`` (8-bit intensity units; a uint16 image is compared at
            ``threshold * 257``, so one frame saved at either depth gives the same scan),
            ``noise_multiple`` and ``contrast`` (the threshold that follows each frame's noise
            and light), ``refinement`` (``"step"``, ``"sub_pixel"``, ``"peak"`` or
            ``"first_crossing"``, the paper's),
            ``columns`` (a count, a list of image columns, or ``{"obstacle_width_m": w,
            "range_m": r}``: columns placed from the table so that no obstacle w wide at
            range r stands between two), ``start``
            (``{"bottom_margin": rows}`` or ``{"per_column": rows}``), ``max_range_m``
            (``inf`` or None: no limit). ``floorscan config --default`` prints each with its
            doc and default; a bad one raises OptionError naming it.

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
        self, table: GroundTable, *, mask: Optional[np.ndarray] = None, **options: Any
    ) -> None:
        if not isinstance(table, GroundTable):
            raise ArgumentTypeError(
                f"table must be a floorscan.GroundTable, got {type(table).__name__}"
            )
        self._table = table
        options = plain(options)
        if mask is not None:
            options["start"] = {
                "per_column": start_rows_from_mask(mask, table.image_width, table.image_height)
            }
        try:
            self._native = _native.VisualRanger(table._native, options)
        except OptionError as e:
            raise in_user_words("ranger", options, e) from None
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
        """The validated options, every field (the ``[ranger]`` config table's serde form)."""
        return self._native.options

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
        return Scan(self._native_for(grey).scan(grey, t))

    def _native_for(self, grey: np.ndarray):
        """The native ranger for ``grey``'s depth: a uint16 image is scanned at the threshold
        x 257 (made on the first such image)."""
        if grey.dtype != np.uint16:
            return self._native
        if self._native16 is None:
            options = self.options
            options["threshold"] *= U16_PER_U8
            self._native16 = _native.VisualRanger(self._table._native, options)
        return self._native16


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
