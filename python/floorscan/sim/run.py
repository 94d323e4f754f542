"""A whole simulated run: the robot drives a tour, the camera renders every frame, and the
truth of every frame is kept. Rendering happens in Rust with the GIL released."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, Optional, Sequence

import numpy as np

from .._atomic import PathLike
from .._native import sim as _native
from ..errors import OptionError
from ..ranging.scan import STATUS_NAMES
from .camera import Camera
from .export import write_dataset
from .render import FrameTruth
from .robot import Robot, Trajectory
from .world import World


class RunTruth:
    """The truth of every frame of a run, as arrays with a leading frame axis N (see
    :class:`FrameTruth` for each field): ``status`` (N, W), ``rows`` (N, W), ``points``
    (N, W, 2), ``points_world``, ``obstacle_world`` (N, W, 2), ``obstacle_z``,
    ``appearance_rows`` (N, W), ``appearance_points`` (N, W, 2), ``pose``,
    ``world_from_camera`` (N, 3)."""

    def __init__(self, native: _native.SimTruth) -> None:
        self._native = native
        self._arrays = native.arrays()

    def __len__(self) -> int:
        return len(self._native)

    def __getattr__(self, name: str) -> np.ndarray:
        aliases = {
            "rows": "row",
            "points": "point",
            "appearance_rows": "appearance_row",
            "appearance_points": "appearance_point",
        }
        key = aliases.get(name, name)
        arrays = self.__dict__.get("_arrays", {})
        if key in arrays:
            return arrays[key]
        raise AttributeError(name)

    @property
    def status_names(self) -> np.ndarray:
        return np.array(STATUS_NAMES, dtype=object)[self._arrays["status"]]

    def to_csv(self, timestamps: np.ndarray) -> str:
        """The truth columns CSV (docs/dataset-format.md), header included."""
        return self._native.to_csv(np.ascontiguousarray(timestamps, dtype=np.float64))


@dataclass
class Run:
    """A simulated run. ``timestamps`` (N,) [s]; ``poses`` (N, 3) true world_from_robot;
    ``odometry`` (N, 3) odometry poses; ``images`` (N, H, W) uint8; ``labels`` (N, H, W) uint8
    or None; ``truth`` :class:`RunTruth` or None; ``exposures`` (N,)."""

    world: World
    camera: Camera
    robot: Robot
    seed: int
    timestamps: np.ndarray
    poses: np.ndarray
    odometry: np.ndarray
    images: np.ndarray
    labels: Optional[np.ndarray]
    truth: Optional[RunTruth]
    exposures: np.ndarray
    max_range_m: float = 10.0
    extras: Dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.timestamps)

    def frame_truth(self, k: int) -> FrameTruth:
        """The truth of frame k (needs labels and truth)."""
        if self.truth is None or self.labels is None:
            raise OptionError("this run was simulated without truth or labels")
        return FrameTruth._from_arrays(self.truth._arrays, k, self.labels[k], self.exposures[k])

    def write_dataset(self, folder: PathLike, **options: Any):
        """Writes the run as a dataset folder; see :func:`floorscan.sim.write_dataset`."""
        return write_dataset(self, folder, **options)


def simulate_run(
    world: World,
    *,
    camera: Optional[Camera] = None,
    robot: Optional[Robot] = None,
    seconds: float = 60.0,
    seed: int = 0,
    waypoints: Optional[Sequence[Sequence[float]]] = None,
    commands: Optional[Sequence[Sequence[float]]] = None,
    start: Optional[Sequence[float]] = None,
    labels: bool = True,
    truth: bool = True,
    max_range_m: float = 10.0,
    threads: int = 1,
) -> Run:
    """Simulates ``seconds`` [s] of the robot in ``world``: the world's tour (or
    ``waypoints`` (K, 2) [m], or velocity ``commands`` rows (duration [s], v [m/s],
    omega [rad/s])) from the world's start pose (or ``start`` = (x, y, yaw)), rendered at the
    robot's frame rate. ``labels``/``truth`` keep the per-pixel labels and per-column truth;
    ``threads`` renders frames in parallel (the result does not depend on it). Deterministic
    per ``seed``.

    >>> run = simulate_run(World.builtin("room"), seconds=1.0)
    >>> run.images.shape, run.poses.shape
    ((11, 240, 320), (11, 3))
    """
    camera = camera if camera is not None else Camera()
    robot = robot if robot is not None else Robot()
    if waypoints is None and commands is None:
        waypoints = world.tour
        if len(waypoints) == 0:
            raise OptionError(f"world {world.name!r} has no tour: give waypoints or commands")
    traj: Trajectory = robot.drive(
        start=tuple(start) if start is not None else world.start,
        seconds=seconds,
        waypoints=waypoints,
        commands=commands,
        seed=seed,
    )
    images, label_images, native_truth, exposures = _native.sim_render_run(
        world._native,
        camera._native,
        np.ascontiguousarray(traj.poses),
        int(seed),
        bool(labels),
        bool(truth),
        float(max_range_m),
        int(threads),
    )
    return Run(
        world=world,
        camera=camera,
        robot=robot,
        seed=int(seed),
        timestamps=traj.timestamps,
        poses=traj.poses,
        odometry=traj.odometry,
        images=images,
        labels=label_images,
        truth=RunTruth(native_truth) if native_truth is not None else None,
        exposures=exposures,
        max_range_m=float(max_range_m),
    )
