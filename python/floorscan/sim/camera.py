"""The simulated camera: a lens model and mount (the same :class:`floorscan.Lens` and
:class:`floorscan.CameraMount` a ground table is built from), an image size, its place on the
robot, and how the sensor forms an image.

Frames: the camera ground frame is the point on the floor below the optical centre, x along the
camera's heading, y left. ``x_m``, ``y_m``, ``yaw_rad`` place it on the robot base (a yaw is a
pan of the camera); tilt and roll belong to the mount.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, Optional, Union

import numpy as np

from .._atomic import PathLike, write_atomic
from .._native import sim as _native
from ..errors import ArgumentTypeError, FileFormatError, OptionError
from ..ranging.ground_table import GroundTable
from ..ranging.lens import CameraMount, Lens
from ._options import as_dict, init_options


@dataclass(frozen=True, init=False)
class Imaging:
    """How the sensor turns light into 8-bit grey values.

    - ``read_noise_dn``: signal-independent noise, standard deviation [DN], in [0, 50]. 1.5.
    - ``shot_noise_gain``: shot noise variance per DN of signal [DN], in [0, 10]. 0.06.
    - ``blur_sigma_px``: optical blur, Gaussian standard deviation [px], in [0, 10]. 0.6.
    - ``vignetting``: brightness lost at the image corners, fraction in [0, 1]. 0.35.
    - ``antialias``: four samples per pixel on edges between surfaces. True.
    """

    read_noise_dn: float = 1.5
    shot_noise_gain: float = 0.06
    blur_sigma_px: float = 0.6
    vignetting: float = 0.35
    antialias: bool = True

    def __init__(self, **options: Any) -> None:
        init_options(self, _native.validate_imaging, _known(self, options))

    @classmethod
    def ideal(cls) -> Imaging:
        """No noise, blur, vignetting or anti-aliasing: the scene's radiance, quantised."""
        return cls(
            read_noise_dn=0.0,
            shot_noise_gain=0.0,
            blur_sigma_px=0.0,
            vignetting=0.0,
            antialias=False,
        )


def _known(obj: Any, options: Dict[str, Any]) -> Dict[str, Any]:
    names = {f for f in obj.__dataclass_fields__}
    unknown = sorted(set(options) - names)
    if unknown:
        raise OptionError(
            f"unknown option(s) {unknown} for {type(obj).__name__} (known: {sorted(names)})"
        )
    return options


class Camera:
    """A camera on the robot.

    Parameters (keyword-only):
        lens: a :class:`floorscan.Lens`; default: a Kannala-Brandt fisheye of about 136 degrees
            horizontal field of view, scaled to the image size.
        mount: a :class:`floorscan.CameraMount`; default 0.40 m high, tilted down 0.6 rad, so
            the floor just in front of the robot is at the bottom of the image.
        width, height: image size [px], 8..8192. Default 320 x 240.
        x_m, y_m, yaw_rad: camera ground frame on the robot base [m, m, rad]. Default
            0.12 m forward of the base, looking ahead.
        imaging: :class:`Imaging` (noise, blur, vignetting). Default ``Imaging()``.

    >>> cam = Camera()
    >>> cam.width, cam.height
    (320, 240)
    >>> x, y = cam.pixel_to_ground(159.5, 239.0)
    >>> 0.0 < x < 0.15 and abs(y) < 1e-9
    True
    """

    __slots__ = ("_native", "_spec")

    def __init__(
        self,
        *,
        lens: Optional[Lens] = None,
        mount: Optional[CameraMount] = None,
        width: int = 320,
        height: int = 240,
        x_m: float = 0.12,
        y_m: float = 0.0,
        yaw_rad: float = 0.0,
        imaging: Optional[Imaging] = None,
    ) -> None:
        spec = json.loads(_native.SimCamera.default_json(int(width), int(height)))
        if lens is not None:
            if not isinstance(lens, Lens):
                raise ArgumentTypeError(f"lens must be a floorscan.Lens, got {type(lens).__name__}")
            spec["lens"] = lens.to_dict()
        if mount is not None:
            if not isinstance(mount, CameraMount):
                raise ArgumentTypeError(
                    f"mount must be a floorscan.CameraMount, got {type(mount).__name__}"
                )
            spec["mount"] = json.loads(mount.to_json())
        spec["robot_from_camera"] = {"x": float(x_m), "y": float(y_m), "yaw": float(yaw_rad)}
        spec["imaging"] = as_dict(imaging if imaging is not None else Imaging())
        self._spec = spec
        self._native = _native.SimCamera.from_json(json.dumps(spec))

    # --- description ------------------------------------------------------------------
    @property
    def lens(self) -> Lens:
        return Lens.from_dict(self._spec["lens"])

    @property
    def mount(self) -> CameraMount:
        return CameraMount(**self._spec["mount"])

    @property
    def width(self) -> int:
        return int(self._spec["width"])

    @property
    def height(self) -> int:
        return int(self._spec["height"])

    @property
    def robot_from_camera(self) -> tuple:
        """(x [m], y [m], yaw [rad]) of the camera ground frame on the robot base."""
        r = self._spec["robot_from_camera"]
        return (r["x"], r["y"], r["yaw"])

    @property
    def imaging(self) -> Imaging:
        return Imaging(**self._spec["imaging"])

    def with_imaging(self, imaging: Imaging) -> Camera:
        """The same camera with other imaging options."""
        x, y, yaw = self.robot_from_camera
        return Camera(
            lens=self.lens,
            mount=self.mount,
            width=self.width,
            height=self.height,
            x_m=x,
            y_m=y,
            yaw_rad=yaw,
            imaging=imaging,
        )

    def rig(self) -> Dict[str, float]:
        """The ``[camera]`` table of a dataset's rig.toml: x, y, yaw, height."""
        x, y, yaw = self.robot_from_camera
        return {"x": x, "y": y, "yaw": yaw, "height": self.mount.height_m}

    # --- exact geometry -----------------------------------------------------------------
    def pixel_to_ground(self, u, v, *, max_range_m: float = math.inf):
        """Exact ground point(s) [m] (camera ground frame) seen at pixel(s) (u, v): the
        lens model through floorscan-core's ``pixel_to_ground``. Scalars give ``(x, y)`` or
        None; arrays give two float64 arrays, NaN where there is no ground."""
        scalar = np.isscalar(u) and np.isscalar(v)
        ub, vb = np.broadcast_arrays(
            np.asarray(u, dtype=np.float64), np.asarray(v, dtype=np.float64)
        )
        x, y = self._native.pixel_to_ground(
            ub.ravel().copy(), vb.ravel().copy(), float(max_range_m)
        )
        if scalar:
            return None if np.isnan(x[0]) else (float(x[0]), float(y[0]))
        return x.reshape(ub.shape), y.reshape(ub.shape)

    def ground_to_pixel(self, x, y):
        """Pixel(s) (u, v) where ground point(s) [m] (camera ground frame) appear. Scalars
        give ``(u, v)`` or None; arrays give two arrays, NaN where not visible."""
        scalar = np.isscalar(x) and np.isscalar(y)
        xb, yb = np.broadcast_arrays(
            np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        )
        u, v = self._native.ground_to_pixel(xb.ravel().copy(), yb.ravel().copy())
        if scalar:
            return None if np.isnan(u[0]) else (float(u[0]), float(v[0]))
        return u.reshape(xb.shape), v.reshape(xb.shape)

    def ground_table(self, *, spacing_px: int = 1, max_range_m: float = 10.0) -> GroundTable:
        """The exact ground table of this camera (what a perfect calibration would give):
        nodes every ``spacing_px`` pixels, no ground beyond ``max_range_m`` [m]."""
        return GroundTable(self._native.ground_table(int(spacing_px), float(max_range_m)))

    # --- files --------------------------------------------------------------------------
    def to_json(self) -> str:
        """The camera as JSON (lens, mount, size, robot_from_camera, imaging)."""
        return json.dumps(self._spec, indent=2)

    @classmethod
    def from_json(cls, text: Union[str, bytes]) -> Camera:
        try:
            d = json.loads(text)
            rig = d["robot_from_camera"]
            return cls(
                lens=Lens.from_dict(d["lens"]),
                mount=CameraMount(**d["mount"]),
                width=d["width"],
                height=d["height"],
                x_m=rig["x"],
                y_m=rig["y"],
                yaw_rad=rig["yaw"],
                imaging=Imaging(**d.get("imaging", {})),
            )
        except (ValueError, KeyError, TypeError) as e:
            raise FileFormatError(f"not a simulator camera description: {e}") from None

    def save(self, path: PathLike) -> Path:
        return write_atomic(path, self.to_json())

    @classmethod
    def load(cls, path: PathLike) -> Camera:
        try:
            return cls.from_json(Path(path).read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError) as e:
            raise FileFormatError(f"cannot read camera file {path}: {e}") from None

    def __repr__(self) -> str:
        return f"Camera({self.width}x{self.height}, lens={self._spec['lens']['model']})"
