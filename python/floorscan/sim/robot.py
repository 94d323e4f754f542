"""The simulated robot: differential drive following waypoints or velocity commands at a
cruise speed, sampled at the camera's frame rate, with wheel odometry that has random and
systematic errors (so maps "bend" as in the paper's Fig. 2 unless corrected)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Optional, Sequence, Tuple

import numpy as np

from .._native import sim as _native
from ..errors import ArgumentTypeError, OptionError
from ._options import as_dict, init_options


@dataclass(frozen=True, init=False)
class OdometryNoise:
    """Wheel odometry errors.

    - ``wheel_sigma_per_sqrt_m``: random error of each wheel's travel [m/sqrt(m)], in [0, 1]:
      after d metres a wheel's error has standard deviation sigma sqrt(d). Default 0.01.
    - ``radius_scale_error``: relative error of the wheel radius the odometry assumes, in
      [-0.5, 0.5]; distances read 1 + this times too long. Default 0.01.
    - ``radius_difference``: relative difference of the right and left wheel radii, in
      [-0.5, 0.5]; straight driving reads as a curve of curvature difference / wheelbase.
      Default 0.004.
    - ``wheelbase_error``: relative error of the wheelbase the odometry assumes, in
      [-0.5, 0.5]; turns read as 1 / (1 + this) of their angle. Default 0.02.
    """

    wheel_sigma_per_sqrt_m: float = 0.01
    radius_scale_error: float = 0.01
    radius_difference: float = 0.004
    wheelbase_error: float = 0.02

    def __init__(self, **options: Any) -> None:
        _check_names(self, options)
        init_options(self, _native.validate_odometry_noise, options)

    @classmethod
    def none(cls) -> OdometryNoise:
        """No odometry error: odometry equals the true trajectory."""
        return cls(
            wheel_sigma_per_sqrt_m=0.0,
            radius_scale_error=0.0,
            radius_difference=0.0,
            wheelbase_error=0.0,
        )


def _check_names(obj: Any, options: dict) -> None:
    names = set(obj.__dataclass_fields__)
    unknown = sorted(set(options) - names)
    if unknown:
        raise OptionError(
            f"unknown option(s) {unknown} for {type(obj).__name__} (known: {sorted(names)})"
        )


@dataclass(frozen=True)
class Trajectory:
    """Robot poses at the frames: ``timestamps`` (N,) [s] from 0; ``poses`` (N, 3) true
    world_from_robot (x [m], y [m], yaw [rad]); ``odometry`` (N, 3) odometry poses (odom frame,
    which starts at the true start pose)."""

    timestamps: np.ndarray
    poses: np.ndarray
    odometry: np.ndarray

    def __len__(self) -> int:
        return len(self.timestamps)


@dataclass(frozen=True, init=False)
class Robot:
    """A differential-drive robot.

    - ``speed_mps``: cruise speed [m/s], in (0, 3]. Default 0.3 (the paper's top speed).
    - ``turn_rate_radps``: largest turn rate [rad/s], in (0, 10]. Default 0.8.
    - ``frame_rate_hz``: camera frame rate [Hz], in (0, 1000]. Default 10.
    - ``wheelbase_m``: distance between the wheels [m], in (0, 5]. Default 0.3.
    - ``waypoint_tolerance_m``: a waypoint is reached within this distance [m]. Default 0.05.
    - ``control_rate_hz``: control and integration steps per second. Default 100.
    - ``odometry``: :class:`OdometryNoise`. Default ``OdometryNoise()``.
    """

    speed_mps: float = 0.3
    turn_rate_radps: float = 0.8
    frame_rate_hz: float = 10.0
    wheelbase_m: float = 0.3
    waypoint_tolerance_m: float = 0.05
    control_rate_hz: float = 100.0
    odometry: OdometryNoise = None  # type: ignore[assignment]

    def __init__(self, **options: Any) -> None:
        _check_names(self, options)
        odometry = options.pop("odometry", None)
        if odometry is None:
            odometry = OdometryNoise()
        if not isinstance(odometry, OdometryNoise):
            raise ArgumentTypeError(
                f"odometry must be an OdometryNoise, got {type(odometry).__name__}"
            )
        for f in self.__dataclass_fields__.values():
            if f.name != "odometry":
                value = options.get(f.name, f.default)
                object.__setattr__(self, f.name, float(value))
        object.__setattr__(self, "odometry", odometry)
        _native.validate_robot_options(json.dumps(self._options()))

    def _options(self) -> dict:
        d = as_dict(self)
        d.pop("odometry")
        return d

    def drive(
        self,
        *,
        start: Tuple[float, float, float],
        seconds: float,
        waypoints: Optional[Sequence[Sequence[float]]] = None,
        commands: Optional[Sequence[Sequence[float]]] = None,
        repeat: bool = True,
        seed: int = 0,
    ) -> Trajectory:
        """Drives from ``start`` (x, y, yaw) for ``seconds`` [s]: through ``waypoints`` (K, 2)
        [m, world frame], in order (again from the first when ``repeat``), or by ``commands``
        rows (duration [s], v [m/s], omega [rad/s]). Frames at k / frame_rate_hz, k = 0..
        seconds * rate. Deterministic per ``seed`` (the odometry's random error)."""
        if (waypoints is None) == (commands is None):
            raise OptionError("give exactly one of `waypoints` and `commands`")
        if waypoints is not None:
            pts = np.asarray(waypoints, dtype=np.float64).reshape(-1, 2)
            motion = {
                "waypoints": {
                    "points": [{"x": x, "y": y} for x, y in pts.tolist()],
                    "repeat": bool(repeat),
                }
            }
        else:
            cmds = np.asarray(commands, dtype=np.float64).reshape(-1, 3)
            motion = {
                "commands": [
                    {"duration_s": d, "v_mps": v, "omega_radps": w} for d, v, w in cmds.tolist()
                ]
            }
        x, y, yaw = (float(c) for c in start)
        t, truth, odo = _native.sim_drive(
            x,
            y,
            yaw,
            json.dumps(motion),
            json.dumps(self._options()),
            json.dumps(as_dict(self.odometry)),
            float(seconds),
            int(seed),
        )
        return Trajectory(timestamps=t, poses=truth, odometry=odo)
