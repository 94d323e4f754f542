"""Rendering one view of a world, with its ground truth."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Sequence, Tuple

import numpy as np

from .._native import sim as _native
from ..errors import ArgumentTypeError
from ..ranging.scan import STATUS_NAMES
from .camera import Camera
from .world import World

PIXEL_LABELS = ("nothing", "carpet", "other_covering", "paper", "obstacle", "ceiling")
"""Names of the pixel label codes 0..5 (label images hold the codes)."""


@dataclass(frozen=True)
class FrameTruth:
    """The truth of one view. Rows are image rows (v = 0 top, pixel centres at integers).

    - ``labels`` (H, W) uint8: what each pixel centre sees, codes of :data:`PIXEL_LABELS`.
    - ``pose`` (3,): world_from_robot; ``world_from_camera`` (3,): the camera ground frame.
    - ``status`` (W,) uint8: per image column, codes of ``floorscan.ranging.scan.STATUS_NAMES``
      (boundary, no_boundary, too_close, invalid); :attr:`status_names` as strings.
    - ``rows`` (W,): boundary row [px], the edge line between the last floor pixel and the
      first obstacle pixel counted from the bottom (a float between their centres); NaN
      unless ``boundary``.
    - ``points`` (W, 2): the floor point at that row, camera ground frame [m] (what an ideal
      range sensor reports); ``points_world`` (W, 2): the same in the world frame.
    - ``obstacle_world`` (W, 2), ``obstacle_z`` (W,): the obstacle surface point just above
      the boundary, world frame [m]; equal to ``points_world`` at height 0 for faces standing
      on the floor, nearer for overhangs.
    - ``appearance_rows`` (W,): the appearance boundary row [px]: edge line below the first
      pixel from the bottom that does not see the floor covering under the camera (paper,
      another covering, an obstacle); ``appearance_points`` (W, 2) its floor point if floor.
    - ``exposure``: the frame's exposure (mean times jitter).
    """

    labels: np.ndarray
    pose: np.ndarray
    world_from_camera: np.ndarray
    status: np.ndarray
    rows: np.ndarray
    points: np.ndarray
    points_world: np.ndarray
    obstacle_world: np.ndarray
    obstacle_z: np.ndarray
    appearance_rows: np.ndarray
    appearance_points: np.ndarray
    exposure: float

    @property
    def status_names(self) -> np.ndarray:
        return np.array(STATUS_NAMES, dtype=object)[self.status]

    @classmethod
    def _from_arrays(
        cls, a: Dict[str, np.ndarray], k: int, labels: np.ndarray, exposure: float
    ) -> FrameTruth:
        return cls(
            labels=labels,
            pose=a["pose"][k],
            world_from_camera=a["world_from_camera"][k],
            status=a["status"][k],
            rows=a["row"][k],
            points=a["point"][k],
            points_world=a["point_world"][k],
            obstacle_world=a["obstacle_world"][k],
            obstacle_z=a["obstacle_z"][k],
            appearance_rows=a["appearance_row"][k],
            appearance_points=a["appearance_point"][k],
            exposure=float(exposure),
        )


def render(
    world: World,
    camera: Camera,
    pose: Sequence[float],
    *,
    seed: int = 0,
    frame: int = 0,
    max_range_m: float = 10.0,
) -> Tuple[np.ndarray, FrameTruth]:
    """Renders what ``camera`` sees from a robot at ``pose`` = (x [m], y [m], yaw [rad])
    (world_from_robot). Returns the (H, W) uint8 image and its :class:`FrameTruth`; boundaries
    beyond ``max_range_m`` [m] count as no_boundary. Deterministic: the sensor noise comes from
    (``seed``, ``frame``).

    >>> image, truth = render(World.builtin("room"), Camera(), (0.5, 0.5, 0.0))
    >>> image.shape, image.dtype, truth.labels.shape
    ((240, 320), dtype('uint8'), (240, 320))
    """
    image, labels, truth, exposure = _render_native(
        world, camera, pose, seed, frame, True, max_range_m
    )
    return image, FrameTruth._from_arrays(truth.arrays(), 0, labels, exposure)


def _render_native(world, camera, pose, seed, frame, truth, max_range_m):
    if not isinstance(world, World):
        raise ArgumentTypeError(f"world must be a floorscan.sim.World, got {type(world).__name__}")
    if not isinstance(camera, Camera):
        raise ArgumentTypeError(
            f"camera must be a floorscan.sim.Camera, got {type(camera).__name__}"
        )
    x, y, yaw = (float(c) for c in pose)
    return _native.sim_render(
        world._native,
        camera._native,
        x,
        y,
        yaw,
        int(seed),
        int(frame),
        bool(truth),
        float(max_range_m),
    )


def render_image(
    world: World, camera: Camera, pose: Sequence[float], *, seed: int = 0, frame: int = 0
) -> np.ndarray:
    """Only the image of :func:`render` (no truth computed)."""
    return _render_native(world, camera, pose, seed, frame, False, 10.0)[0]
