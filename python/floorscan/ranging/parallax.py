"""The floor-parallax cue (``floorscan_core::floor_parallax``): the edge ranger's boundaries
checked against the motion since an earlier frame. A boundary whose image rows above it moved
as floor does (the ground table's homography between the two views) rather than as a surface
standing on it is the floor's own edge (a grout line, a plank joint, a printed pattern), and
its column is scanned on above it. Needs poses (odometry): a single image, a robot standing,
or a camera turning about its own centre is ranged as the edge ranger alone ranges it.

The config's ``[parallax]`` table (``enabled = true``) turns it on for ``run``, ``node``,
``fleet`` and ``eval``; its fields are ``ParallaxOptions``' (``floorscan config --default``).
"""

from __future__ import annotations

import math
from typing import Any, Dict, Optional, Sequence

import numpy as np

from .._native import ranging as _native
from ..errors import ArgumentTypeError, ImageError, OptionError
from ..formats.image_io import as_grey
from ..options import plain
from .ground_table import GroundTable
from .ranger import VisualRanger
from .scan import Scan


class ParallaxRanger:
    """An edge ranger with the floor-parallax cue.

    Parameters:
        ranger: the :class:`VisualRanger` whose boundaries are checked (its table and
            columns are this ranger's).
        **options: any field of the core's ``ParallaxOptions`` (``min_baseline_m``,
            ``min_turn_baseline_m``, ``history_frames``, ``rows_above_fraction``, ``min_texture_grey``,
            ``blur_sigma_px``, ``refine_range_m``, ``min_log_likelihood_ratio``,
            ``max_vetoes``, ``base_line_gap_m``, ``search_above_vetoed``,
            ``min_standing_log_likelihood_ratio``, ``memory_min_frames``, ``memory_cell_m``,
            ``memory_radius_m``; ``enabled`` is the config's switch and is ignored here); a bad
            one raises OptionError naming it.

    :meth:`scan` takes the camera ground frame's pose ``world_from_camera`` (odometry
    composed with the mount); without it the scan is the edge ranger's.
    """

    def __init__(self, ranger: VisualRanger, **options: Any) -> None:
        if not isinstance(ranger, VisualRanger):
            raise ArgumentTypeError(
                f"ranger must be a floorscan.VisualRanger (the edge ranger), got "
                f"{type(ranger).__name__}"
            )
        self.edge = ranger
        self._native = _native.FloorParallax(ranger.table._native, plain(options))
        self.last_report: Dict[str, float] = {"baseline_m": 0.0, "vetoes": 0, "noise_grey": 0.0}
        """What the last :meth:`scan` did: the camera travel to the earlier frame compared with
        [m] (0: none), boundaries found to be the floor's own, the floor's residual noise."""

    @property
    def table(self) -> GroundTable:
        return self.edge.table

    @property
    def columns(self) -> np.ndarray:
        return self.edge.columns

    @property
    def options(self) -> Dict[str, Any]:
        """The parallax options, every field (the ``[parallax]`` table's serde form)."""
        return self._native.options

    def reset(self) -> None:
        """Forgets the earlier frames (a jump in the poses, another recording)."""
        self._native.reset()

    def scan(
        self,
        image: np.ndarray,
        *,
        timestamp: float = 0.0,
        world_from_camera: Optional[Sequence[float]] = None,
    ) -> Scan:
        """Scans one (H, W) uint8/uint16 image (colour is converted to grey) and checks its
        boundaries against the earlier frames when ``world_from_camera`` (x, y, yaw) is given;
        the frame is kept for later ones. The GIL is released meanwhile."""
        grey = as_grey(image)
        t = self.table
        if grey.shape != (t.image_height, t.image_width):
            raise ImageError(
                f"image is {grey.shape[1]} x {grey.shape[0]} (W x H) but the calibration table is "
                f"for {t.image_width} x {t.image_height}"
            )
        try:
            ts = float(timestamp)
        except (TypeError, ValueError):
            raise OptionError(
                f"invalid option `timestamp`: must be a number [s], got {timestamp!r}"
            ) from None
        pose = None
        if world_from_camera is not None:
            try:
                pose = tuple(float(v) for v in world_from_camera)
            except (TypeError, ValueError):
                raise OptionError(
                    f"invalid option `world_from_camera`: must be (x, y, yaw), got "
                    f"{world_from_camera!r}"
                ) from None
            if len(pose) != 3 or not all(math.isfinite(v) for v in pose):
                raise OptionError(
                    f"invalid option `world_from_camera`: must be 3 finite numbers (x, y, yaw), "
                    f"got {world_from_camera!r}"
                )
        native, report = self._native.scan(self.edge._native_for(grey), grey, ts, pose)
        self.last_report = dict(zip(("baseline_m", "vetoes", "noise_grey"), report))
        return Scan(native)
