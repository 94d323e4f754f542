"""The appearance range sensor: ranging that does not rely on the texture assumption (the
paper's future work; Ulrich & Nourbakhsh 2000, Lorigo et al. 1997).

A model of what the floor looks like (histograms of colour and local texture) is learned from a
band of floor just in front of the robot (the bottom of the image) and blended over frames;
per sampled column, the lowest row of the first run of rows that do not look like floor is the
boundary, looked up in the ground table like the edge ranger's (same statuses). Colour images
are first-class; greyscale works too (every channel the same).
"""

from __future__ import annotations

import math
from typing import Any, Dict, Optional

import numpy as np

from .._native import ranging as _native
from ..errors import ImageError, ImageTypeError, OptionError
from ..options import plain
from .ground_table import GroundTable
from .ranger import start_rows_from_mask
from .scan import Scan

NO_SAMPLE = 2**32 - 1
"""An unused slot of :meth:`AppearanceRanger.boundary_samples`."""


class AppearanceRanger:
    """Turns colour (or grey) images into :class:`~floorscan.Scan` s by floor appearance.

    Parameters (keyword-only after ``table``):
        table: the :class:`GroundTable` of the camera (fixes the image size).
        mask: optional (H, W) boolean floor-visibility mask (sets ``start``).
        **options: any field of the core's ``AppearanceOptions`` (its serde form; the others
            take their defaults, ``floorscan.options.defaults("appearance")``): ``columns``,
            ``start``, ``max_range_m`` (as the edge ranger's), ``reference_fraction``,
            ``reference_width_fraction``,
            ``features`` (``"colour_and_texture"`` or ``"colour"``), ``min_floor_share``,
            ``intensity_reach_bins``, ``patch_half_width_px``, ``min_run_px``,
            ``adaptation_rate``, and the driven-over refresh's ``driven_floor_radius_m``,
            ``driven_floor_samples``, ``driven_floor_half_life_frames`` (see
            :meth:`learn_driven_floor`). ``floorscan config --default`` prints each with its doc and
            default; a bad one raises OptionError naming it.

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
        self, table: GroundTable, *, mask: Optional[np.ndarray] = None, **options: Any
    ) -> None:
        if not isinstance(table, GroundTable):
            raise TypeError(f"table must be a floorscan.GroundTable, got {type(table).__name__}")
        self._table = table
        options = plain(options)
        if mask is not None:
            options["start"] = {
                "per_column": start_rows_from_mask(mask, table.image_width, table.image_height)
            }
        self._native = _native.AppearanceRanger(table._native, options)
        self.last_scan: Optional[Scan] = None

    @property
    def table(self) -> GroundTable:
        return self._table

    @property
    def columns(self) -> np.ndarray:
        """Sampled image columns [px], in output order."""
        return self._native.columns

    @property
    def options(self) -> Dict[str, Any]:
        """The validated options, every field (the core's serde form)."""
        return self._native.options

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
        self.last_scan = Scan(self._native.scan(arr, t))
        return self.last_scan

    def boundary_samples(self) -> np.ndarray:
        """Per sampled column of the last scan (output order), the pixels of the run of
        non-floor rows that made its boundary, as packed (colour, texture) bins:
        (columns, 4) uint32, ``NO_SAMPLE`` (2**32 - 1) in unused slots and for readings other
        than a boundary. Keep those of a boundary and, once the robot has driven through it,
        hand them to :meth:`learn_driven_floor`."""
        return self._native.boundary_samples()

    @property
    def driven_floor_columns(self) -> np.ndarray:
        """Per sampled column of the last scan (bool): whether its scan crossed at least
        ``min_run_px`` rows that look like floor only as floor the robot drove over (the
        fused ranger keeps this ranger's floor where an edge lies on that floor's border, see
        :attr:`driven_floor_borders`)."""
        return self._native.driven_floor_columns

    @property
    def driven_floor_borders(self) -> np.ndarray:
        """Per sampled column of the last scan (float64): the image row [px] of the first
        border, scanning up, between the reference's floor and driven-over floor (a rug's
        edge); NaN where the column crossed none. The fused ranger keeps this ranger's "only
        floor" reading where the edge ranger's boundary lies on that border."""
        return self._native.driven_floor_borders

    def learn_driven_floor(self, samples: np.ndarray) -> int:
        """Learns ``samples`` (from :meth:`boundary_samples`) as floor from the next frame on:
        the boundary they came from was driven through, so it was floor (a rug, a doorway's
        linoleum, a sunlit patch). Call it right after scanning the frame taken where the robot
        drove through: only the samples that frame's reference band confirms (the reference's
        own model takes them as floor there) are learned, so a boundary the robot only seemed
        to reach (odometry drift onto a wall's base) teaches nothing. A colour or texture is
        floor once ``driven_floor_samples`` learned pixels lie within one bin of it; they fade
        with ``driven_floor_half_life_frames``. ``floorscan run``, ``eval`` and ``drive`` do
        this from their poses (``driven_floor_radius_m``). Returns the samples learned; a
        value that is not a packed sample raises OptionError and nothing is learned."""
        arr = np.ascontiguousarray(np.asarray(samples).reshape(-1))
        if arr.dtype != np.uint32:
            if arr.size and (
                not np.issubdtype(arr.dtype, np.integer) or arr.min() < 0 or arr.max() > NO_SAMPLE
            ):
                raise OptionError(
                    "invalid option `samples`: must be packed samples (uint32) from boundary_samples()"
                )
            arr = arr.astype(np.uint32)
        return int(self._native.learn_driven_floor(arr))


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
