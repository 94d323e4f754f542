"""Where the camera sits on the robot: the dataset's ``rig.toml``.

```toml
[camera]
x = 0.10       # m, camera ground frame origin in the robot base frame (x forward)
y = 0.0        # m, (y left)
yaw = 0.0      # rad, camera heading relative to the robot's (CCW)
height = 0.40  # m, optical centre above the floor (informational: the ground table holds the geometry)
```
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Dict, Tuple

from .._atomic import PathLike, write_atomic
from ..errors import ConfigError
from .toml_file import dumps_toml, load_toml


@dataclass(frozen=True)
class Rig:
    """Pose of the camera ground frame on the robot base [m, m, rad] and the camera height [m]."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    height: float = 0.4

    def __post_init__(self) -> None:
        for k, v in asdict(self).items():
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
                raise ConfigError(f"rig: `camera.{k}` must be a finite number, got {v!r}")
        if self.height <= 0:
            raise ConfigError(f"rig: `camera.height` must be > 0, got {self.height}")

    @property
    def robot_from_camera(self) -> Tuple[float, float, float]:
        """(x, y, yaw) of the camera ground frame in the robot base frame."""
        return (self.x, self.y, self.yaw)

    @classmethod
    def from_dict(cls, d: Dict[str, Any], *, source: str = "rig") -> Rig:
        cam = d.get("camera")
        if not isinstance(cam, dict):
            raise ConfigError(f"{source}: missing table [camera]")
        unknown = set(d) - {"camera"}
        if unknown:
            raise ConfigError(f"{source}: unknown key `{sorted(unknown)[0]}`")
        bad = set(cam) - {"x", "y", "yaw", "height"}
        if bad:
            raise ConfigError(
                f"{source}: unknown key `camera.{sorted(bad)[0]}` (expected x, y, yaw, height)"
            )
        return cls(**{k: cam[k] for k in cam})

    def to_toml(self) -> str:
        return dumps_toml({"camera": asdict(self)})


def read_rig(path: PathLike) -> Rig:
    path = Path(path)
    return Rig.from_dict(load_toml(path), source=str(path))


def write_rig(path: PathLike, rig: Rig) -> Path:
    return write_atomic(path, rig.to_toml())
