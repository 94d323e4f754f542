"""Lens models and camera mounts (the same models the Rust core and the simulator use).

Optical frame: x right, y down, z along the optical axis (OpenCV). Pixels (u, v) have their
origin at the centre of the top-left pixel. A mount places the camera above its ground frame
(origin on the floor below the camera, x along its heading, y left, z up).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from typing import Any, Dict

from ..errors import OptionError


def _finite(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise OptionError(f"invalid option `{name}`: must be finite, got {value}")
    return value


@dataclass(frozen=True)
class Lens:
    """A lens model. Build one with :meth:`pinhole`, :meth:`pinhole_radial`,
    :meth:`equidistant` or :meth:`kannala_brandt`."""

    model: str
    params: Dict[str, float]

    @classmethod
    def pinhole(cls, *, fx: float, fy: float, cx: float, cy: float) -> Lens:
        """Ideal perspective projection [px]."""
        return cls._make("pinhole", fx=fx, fy=fy, cx=cx, cy=cy)

    @classmethod
    def pinhole_radial(
        cls,
        *,
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        k1: float = 0.0,
        k2: float = 0.0,
        p1: float = 0.0,
        p2: float = 0.0,
        k3: float = 0.0,
    ) -> Lens:
        """Perspective projection with OpenCV's plumb_bob distortion (k1, k2, p1, p2, k3)."""
        return cls._make(
            "pinhole_radial", fx=fx, fy=fy, cx=cx, cy=cy, k1=k1, k2=k2, p1=p1, p2=p2, k3=k3
        )

    @classmethod
    def equidistant(cls, *, f: float, cx: float, cy: float) -> Lens:
        """Equidistant fisheye: image radius = f * angle from the optical axis [px]."""
        return cls._make("equidistant", f=f, cx=cx, cy=cy)

    @classmethod
    def kannala_brandt(
        cls,
        *,
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        k1: float = 0.0,
        k2: float = 0.0,
        k3: float = 0.0,
        k4: float = 0.0,
    ) -> Lens:
        """OpenCV's fisheye model: theta_d = theta (1 + k1 theta^2 + ... + k4 theta^8)."""
        return cls._make("kannala_brandt", fx=fx, fy=fy, cx=cx, cy=cy, k1=k1, k2=k2, k3=k3, k4=k4)

    @classmethod
    def _make(cls, model: str, **params: float) -> Lens:
        clean = {k: _finite(k, v) for k, v in params.items()}
        for k in ("fx", "fy", "f"):
            if k in clean and clean[k] <= 0:
                raise OptionError(f"invalid option `{k}`: focal length must be > 0, got {clean[k]}")
        return cls(model, clean)

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> Lens:
        """From ``{"model": ..., <params>}`` (the form in config files and table metadata)."""
        d = dict(d)
        model = d.pop("model", None)
        makers = {
            "pinhole": cls.pinhole,
            "pinhole_radial": cls.pinhole_radial,
            "equidistant": cls.equidistant,
            "kannala_brandt": cls.kannala_brandt,
        }
        if model not in makers:
            raise OptionError(
                f"invalid option `lens.model`: expected one of {sorted(makers)}, got {model!r}"
            )
        try:
            return makers[model](**d)
        except TypeError as e:
            raise OptionError(f"invalid lens parameters for {model}: {e}") from None

    def to_dict(self) -> Dict[str, Any]:
        return {"model": self.model, **self.params}

    def to_json(self) -> str:
        return json.dumps(self.to_dict())


@dataclass(frozen=True)
class CameraMount:
    """Camera above its ground frame: ``height_m`` [m] > 0, ``tilt_rad`` [rad] downward tilt of
    the optical axis below the horizontal, ``roll_rad`` [rad] about the optical axis."""

    height_m: float
    tilt_rad: float
    roll_rad: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.height_m) and self.height_m > 0):
            raise OptionError(f"invalid option `height_m`: must be > 0, got {self.height_m}")
        _finite("tilt_rad", self.tilt_rad)
        _finite("roll_rad", self.roll_rad)

    def to_json(self) -> str:
        return json.dumps(asdict(self))
