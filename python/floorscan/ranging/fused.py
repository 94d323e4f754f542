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

SNAP_ROWS = 3.0
"""Default ``snap_rows``."""
SNAP_FRACTION = 0.08
"""Default ``snap_fraction``: on the simulated carpets the appearance boundary lies a median 7-18
rows of 240 above a right edge (a grey skirting board looks like the grey carpet), on tiles and
planks a median 62-93 rows above a wrong one (10th percentile 22-46):
``.venv/bin/python bench/fusion_gaps.py``."""


TEXTURE_SHARE = 0.15
"""Default ``texture_share``, chosen on 20 s of each simulated world (seed 0,
``.venv/bin/python bench/fusion_gaps.py``): on the carpets at most 3 % of a frame's edge
boundaries lie farther than the snap distance below an appearance boundary (90th
percentile), on tiles a median 37 %. Over the whole simulated suite (31 scenarios, other seeds
and a wide lens among them) 0.15 against off: all columns 27.0 -> 23.2 % wrong, tiles 57 ->
36 %, patterned carpet 88 -> 81 %, planks 19 -> 18 %, the carpets unchanged (4.1 %); the real
floor set 81.2 -> 82.3 % (the living rooms' parquet and rugs 1.4-3.6 points worse, the mall's
tiles unchanged). Over both sets together 0.15 has fewer wrong columns (EVALUATION.md, "Range
sensor kinds"); 1 turns it off."""


class FusedRanger:
    """Edge and appearance ranging fused per column.

    Parameters:
        edge: a :class:`VisualRanger`; appearance: an :class:`AppearanceRanger` of the same
            table and columns.
        snap_rows: largest distance [px rows] at which the edge reading replaces the appearance
            boundary, finite, >= 0. Default :data:`SNAP_ROWS` (3).
        snap_fraction: the same distance as a share of the image height, in [0, 1]; the
            larger of the two applies. Default :data:`SNAP_FRACTION` (0.08).
        texture_share: in [0, 1]: a frame in which more than this share of the edge ranger's
            boundaries lie farther than the snap distance below an appearance boundary breaks
            the texture assumption (grout, joints, a printed pattern), and its columns where
            the appearance ranger saw only floor take the appearance reading where the edge
            ranger found a boundary, an edge it could not place or a too-close edge
            (elsewhere such columns take the edge's: a grey obstacle on a grey floor). A frame
            that cannot show a textured floor (fewer than 3 columns, or no more than this share
            of the edge ranger's boundary columns, have an appearance boundary to compare with)
            keeps the judgement of the frames before it (:attr:`textured`), for at most 50
            frames in a row (``floorscan_core::fusion::TEXTURE_MEMORY_FRAMES``);
            :meth:`reset_model` forgets it. 1 turns it off.
            Default :data:`TEXTURE_SHARE` (0.15).
    """

    def __init__(
        self,
        edge: VisualRanger,
        appearance: AppearanceRanger,
        *,
        snap_rows: float = SNAP_ROWS,
        snap_fraction: float = SNAP_FRACTION,
        texture_share: float = TEXTURE_SHARE,
    ) -> None:
        if not np.array_equal(edge.columns, appearance.columns):
            raise OptionError("invalid option `columns`: the two rangers sample different columns")
        s = float(snap_rows)
        if not (math.isfinite(s) and s >= 0):
            raise OptionError(
                f"invalid option `snap_rows`: must be finite and >= 0, got {snap_rows}"
            )
        f = float(snap_fraction)
        if not (math.isfinite(f) and 0.0 <= f <= 1.0):
            raise OptionError(
                f"invalid option `snap_fraction`: must be in [0, 1], got {snap_fraction}"
            )
        t = float(texture_share)
        if not (math.isfinite(t) and 0.0 <= t <= 1.0):
            raise OptionError(
                f"invalid option `texture_share`: must be in [0, 1], got {texture_share}"
            )
        self.edge, self.appearance, self.snap_rows, self.snap_fraction = edge, appearance, s, f
        self.texture_share = t
        self._snap = max(s, f * edge.table.image_height)
        self._textured, self._inherited = False, 0

    @property
    def textured(self) -> bool:
        """Whether the last frames' floor broke the texture assumption."""
        return self._textured

    def reset_model(self) -> None:
        """Forgets the learned floor and the judgement of its texture (e.g. on entering
        another building)."""
        self.appearance.reset_model()
        self._textured, self._inherited = False, 0

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
            "snap_fraction": self.snap_fraction,
            "texture_share": self.texture_share,
        }

    def scan(self, image: np.ndarray, *, timestamp: float = 0.0) -> Scan:
        """Scans one image with both rangers (colour goes to the appearance ranger, its grey
        conversion to the edge ranger) and fuses the two scans."""
        e = self.edge.scan(image, timestamp=timestamp)
        a = self.appearance.scan(image, timestamp=timestamp)
        fused, self._textured, self._inherited = _native.fuse(
            e._native,
            a._native,
            self._snap,
            self.texture_share,
            self._textured,
            self._inherited,
            self.appearance.driven_floor_borders,
        )
        return Scan(fused)
