"""The fused range sensor: the edge and appearance rangers on the same frame and columns,
fused per column (``floorscan_core::fusion``): the edge reading where its first edge lies within
``snap_rows`` of the appearance boundary (the edge places it to a fraction of a row) or where
the appearance ranger saw only floor (an obstacle that looks like the floor), the appearance
reading elsewhere (a grout line or reflection below the appearance boundary is not an
obstacle)."""

from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .._native import ranging as _native
from ..errors import OptionError
from ..options import plain
from .appearance import AppearanceRanger
from .ranger import VisualRanger
from .scan import Scan

FUSION_OPTIONS = ("snap_rows", "snap_fraction", "texture_share")
"""The fusion's options (the core's ``FusionOptions``: defaults, docs and checks there)."""


class FusedRanger:
    """Edge and appearance ranging fused per column.

    Parameters:
        edge: a :class:`VisualRanger`; appearance: an :class:`AppearanceRanger` of the same
            table and columns.
        snap_rows: largest distance [px rows] at which the edge reading replaces the appearance
            boundary, finite, >= 0 (default: ``FusionOptions``', 3).
        snap_fraction: the same distance as a share of the image height, in [0, 1]; the
            larger of the two applies (default 0.08).
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
            :meth:`reset_model` forgets it. 1 turns it off (default 0.15).

    The three are the core's ``FusionOptions`` (``floorscan.options.defaults("fusion")``
    gives the defaults, ``field_docs("fusion")`` their reasons); a bad one is an
    :class:`~floorscan.OptionError` naming it.
    """

    def __init__(self, edge: VisualRanger, appearance: AppearanceRanger, **options: Any) -> None:
        if not np.array_equal(edge.columns, appearance.columns):
            raise OptionError("invalid option `columns`: the two rangers sample different columns")
        unknown = sorted(set(options) - set(FUSION_OPTIONS))
        if unknown:
            raise OptionError(
                f"invalid option `{unknown[0]}`: unknown option, expected one of "
                + ", ".join(f"`{k}`" for k in FUSION_OPTIONS)
            )
        self._options = _native.check_fusion_options(plain(options))
        self.edge, self.appearance = edge, appearance
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
    def snap_rows(self) -> float:
        return self._options["snap_rows"]

    @property
    def snap_fraction(self) -> float:
        return self._options["snap_fraction"]

    @property
    def texture_share(self) -> float:
        return self._options["texture_share"]

    @property
    def options(self) -> Dict[str, Any]:
        return {"edge": self.edge.options, "appearance": self.appearance.options, **self._options}

    def scan(self, image: np.ndarray, *, timestamp: float = 0.0) -> Scan:
        """Scans one image with both rangers (colour goes to the appearance ranger, its grey
        conversion to the edge ranger) and fuses the two scans."""
        e = self.edge.scan(image, timestamp=timestamp)
        a = self.appearance.scan(image, timestamp=timestamp)
        fused, self._textured, self._inherited = _native.fuse(
            e._native,
            a._native,
            self._options,
            self.edge.table.image_height,
            self._textured,
            self._inherited,
            self.appearance.driven_floor_borders,
        )
        return Scan(fused)
