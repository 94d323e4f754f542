"""The fused range sensor: the edge and appearance rangers on the same frame and columns,
fused per column (``floorscan_core::fusion``): the edge reading where its first edge lies within
``snap_rows`` of the appearance boundary (the edge places it to a fraction of a row) or where
the appearance ranger saw only floor (an obstacle that looks like the floor), the appearance
reading elsewhere (a grout line or reflection below the appearance boundary is not an
obstacle)."""

from __future__ import annotations

import math
from typing import Any, Dict

import numpy as np

from .._native import ranging as _native
from ..errors import OptionError
from .appearance import AppearanceRanger
from .ranger import VisualRanger
from .scan import Scan


class FusedRanger:
    """Edge and appearance ranging fused per column.

    Parameters:
        edge: a :class:`VisualRanger`; appearance: an :class:`AppearanceRanger` of the same
            table and columns.
        snap_rows: largest distance [px rows] at which the edge reading replaces the appearance
            boundary, finite, >= 0. Default 3.
    """

    def __init__(
        self, edge: VisualRanger, appearance: AppearanceRanger, *, snap_rows: float = 3.0
    ) -> None:
        if not np.array_equal(edge.columns, appearance.columns):
            raise OptionError("invalid option `columns`: the two rangers sample different columns")
        s = float(snap_rows)
        if not (math.isfinite(s) and s >= 0):
            raise OptionError(
                f"invalid option `snap_rows`: must be finite and >= 0, got {snap_rows}"
            )
        self.edge, self.appearance, self.snap_rows = edge, appearance, s

    @property
    def table(self):
        return self.edge.table

    @property
    def columns(self) -> np.ndarray:
        return self.edge.columns

    @property
    def options(self) -> Dict[str, Any]:
        return {
            "edge": self.edge.options,
            "appearance": self.appearance.options,
            "snap_rows": self.snap_rows,
        }

    def scan(self, image: np.ndarray, *, timestamp: float = 0.0) -> Scan:
        """Scans one image with both rangers (colour goes to the appearance ranger, its grey
        conversion to the edge ranger) and fuses the two scans."""
        e = self.edge.scan(image, timestamp=timestamp)
        a = self.appearance.scan(image, timestamp=timestamp)
        return Scan(_native.fuse(e._native, a._native, self.snap_rows))
