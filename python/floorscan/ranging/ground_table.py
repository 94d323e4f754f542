"""The calibration lookup table (paper III.B): image pixel -> ground point in the camera ground
frame (x forward, y left, metres), by bilinear interpolation of a regular grid of nodes.

File format: JSON, documented in ``docs/formats.md`` (``format = "floorscan.ground_table"``,
``version = 1``, or ``2`` when the table carries per-node predicted errors).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Tuple

import numpy as np

from .._atomic import PathLike, write_atomic
from .._native import ranging as _native
from ..errors import FileFormatError, FloorscanError, TableError
from .lens import CameraMount, Lens


class GroundTable:
    """Image-to-ground lookup table for one image size.

    Nodes sit every ``spacing_px`` pixels in u and v, starting at pixel (0, 0) and covering the
    whole image. A node holds a ground point [m] or "no ground" (NaN).
    """

    __slots__ = ("_native",)

    def __init__(self, native: _native.GroundTable) -> None:
        self._native = native

    # --- construction -------------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        x_m: np.ndarray,
        y_m: np.ndarray,
        *,
        image_width: int,
        image_height: int,
        spacing_px: int,
    ) -> GroundTable:
        """From (nodes_v, nodes_u) arrays of ground x and y [m]; NaN marks "no ground".

        >>> import numpy as np
        >>> nu, nv = GroundTable.node_shape_for(image_width=33, image_height=17, spacing_px=8)
        >>> (nu, nv)
        (5, 3)
        >>> t = GroundTable.from_arrays(np.ones((nv, nu)), np.zeros((nv, nu)),
        ...                             image_width=33, image_height=17, spacing_px=8)
        >>> t.lookup(10.0, 5.0)
        (1.0, 0.0)
        """
        x = np.asarray(x_m, dtype=np.float64)
        y = np.asarray(y_m, dtype=np.float64)
        nu, nv = cls.node_shape_for(
            image_width=image_width, image_height=image_height, spacing_px=spacing_px
        )
        for name, a in (("x_m", x), ("y_m", y)):
            if a.shape != (nv, nu):
                raise TableError(
                    f"{name} must have shape (nodes_v, nodes_u) = ({nv}, {nu}) for a "
                    f"{image_width} x {image_height} image at {spacing_px} px, got {a.shape}"
                )
        return cls(
            _native.GroundTable.from_arrays(
                int(image_width),
                int(image_height),
                int(spacing_px),
                x.ravel().copy(),
                y.ravel().copy(),
            )
        )

    @classmethod
    def from_function(
        cls,
        ground_of_pixel: Callable[[np.ndarray, np.ndarray], Tuple[np.ndarray, np.ndarray]],
        *,
        image_width: int,
        image_height: int,
        spacing_px: int,
    ) -> GroundTable:
        """By evaluating ``ground_of_pixel(u, v) -> (x, y)`` (vectorised, NaN for no ground) on
        the node grid."""
        nu, nv = cls.node_shape_for(
            image_width=image_width, image_height=image_height, spacing_px=spacing_px
        )
        v, u = np.mgrid[0:nv, 0:nu].astype(np.float64) * spacing_px
        x, y = ground_of_pixel(u, v)
        return cls.from_arrays(
            np.broadcast_to(x, u.shape),
            np.broadcast_to(y, u.shape),
            image_width=image_width,
            image_height=image_height,
            spacing_px=spacing_px,
        )

    @classmethod
    def from_camera(
        cls,
        lens: Lens,
        mount: CameraMount,
        *,
        image_width: int,
        image_height: int,
        spacing_px: int = 8,
        max_range_m: float = 10.0,
    ) -> GroundTable:
        """From a lens model and mount (for users with OpenCV intrinsics). "No ground" above
        the horizon and beyond ``max_range_m`` [m]."""
        return cls(
            _native.GroundTable.from_camera(
                lens.to_dict(),
                dataclasses.asdict(mount),
                int(image_width),
                int(image_height),
                int(spacing_px),
                float(max_range_m),
            )
        )

    @staticmethod
    def node_shape_for(*, image_width: int, image_height: int, spacing_px: int) -> Tuple[int, int]:
        """(nodes_u, nodes_v) of a table for this image size and spacing."""
        if spacing_px < 1:
            raise TableError(f"spacing_px must be at least 1, got {spacing_px}")
        return (-(-(image_width - 1) // spacing_px) + 1, -(-(image_height - 1) // spacing_px) + 1)

    # --- queries ------------------------------------------------------------------------
    @property
    def image_width(self) -> int:
        return self._native.image_width

    @property
    def image_height(self) -> int:
        return self._native.image_height

    @property
    def spacing_px(self) -> int:
        return self._native.spacing_px

    @property
    def nodes(self) -> Tuple[np.ndarray, np.ndarray]:
        """Node ground points: two (nodes_v, nodes_u) float64 arrays [m], NaN for no ground."""
        return self._native.node_arrays()

    @property
    def metadata(self) -> Dict[str, Any]:
        """Free-form provenance saved with the table (source, calibration report summary)."""
        return self._native.metadata()

    def with_metadata(self, metadata: Dict[str, Any]) -> GroundTable:
        """A copy with ``metadata`` replacing the table's metadata."""
        return GroundTable(self._native.with_metadata(metadata))

    def lookup(self, u, v):
        """Ground point(s) [m] seen at pixel(s) (u, v). Scalars give a tuple ``(x, y)`` or
        ``None``; arrays give two float64 arrays with NaN where there is no ground."""
        if np.isscalar(u) and np.isscalar(v):
            x, y = self._native.lookup(np.array([float(u)]), np.array([float(v)]))
            return None if np.isnan(x[0]) else (float(x[0]), float(y[0]))
        ua = np.ascontiguousarray(u, dtype=np.float64)
        va = np.ascontiguousarray(v, dtype=np.float64)
        ub, vb = np.broadcast_arrays(ua, va)
        x, y = self._native.lookup(ub.ravel().copy(), vb.ravel().copy())
        return x.reshape(ub.shape), y.reshape(ub.shape)

    @property
    def error_m(self) -> Optional[np.ndarray]:
        """Predicted floor-position error of each node [m] ((nodes_v, nodes_u), NaN where
        unknown or no ground), the calibration's error bar (file version 2); None when the
        table carries none."""
        return self._native.node_errors()

    def with_errors(self, error_m: np.ndarray) -> GroundTable:
        """A copy carrying ``error_m`` ((nodes_v, nodes_u) [m], NaN unknown) per node.

        >>> import numpy as np
        >>> t = GroundTable.from_arrays(np.ones((3, 5)), np.zeros((3, 5)),
        ...                             image_width=33, image_height=17, spacing_px=8)
        >>> t = t.with_errors(np.full((3, 5), 0.02))
        >>> float(t.lookup_error(10.0, 5.0))
        0.02
        """
        e = np.asarray(error_m, dtype=np.float64)
        nu, nv = self.node_shape_for(
            image_width=self.image_width,
            image_height=self.image_height,
            spacing_px=self.spacing_px,
        )
        if e.shape != (nv, nu):
            raise TableError(f"error_m must have shape ({nv}, {nu}), got {e.shape}")
        return GroundTable(self._native.with_errors(e.ravel().copy()))

    def lookup_error(self, u, v):
        """Predicted floor-position error(s) [m] at pixel(s) (u, v), bilinear between nodes:
        a float (NaN where unknown or no ground) for scalars, else an array."""
        ub, vb = np.broadcast_arrays(np.asarray(u, np.float64), np.asarray(v, np.float64))
        e = self._native.lookup_error(ub.ravel().copy(), vb.ravel().copy()).reshape(ub.shape)
        return float(e) if e.ndim == 0 else e

    # --- files --------------------------------------------------------------------------
    def to_json(self) -> str:
        return self._native.to_json()

    @classmethod
    def from_json(cls, text: str) -> GroundTable:
        """Parses the JSON file format (docs/formats.md); FileFormatError if damaged."""
        if not isinstance(text, str):
            raise FileFormatError(f"a ground table is JSON text, got {type(text).__name__}")
        return cls(_native.GroundTable.from_json(text))

    def save(self, path: PathLike) -> Path:
        """Writes the table as JSON, atomically."""
        return write_atomic(path, self.to_json())

    @classmethod
    def load(cls, path: PathLike) -> GroundTable:
        """Reads a table file; a damaged file or another version raises FileFormatError."""
        try:
            text = Path(path).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise FileFormatError(f"cannot read ground table {path}: {e}") from None
        try:
            return cls.from_json(text)
        except FloorscanError as e:
            # the same class (FileFormatError, UnsupportedVersionError, TableError), the file named
            raise type(e)(f"{path}: {e}") from None

    def __eq__(self, other: object) -> bool:
        return isinstance(other, GroundTable) and self._native == other._native

    def __repr__(self) -> str:
        return f"GroundTable({self.image_width}x{self.image_height}, spacing_px={self.spacing_px})"
