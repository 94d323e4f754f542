"""floorscan.sim: a simulated office building with exact ground truth.

Worlds (:class:`World`: ``corridor``, ``room``, ``lab``, ``tiles`` or a world file), a wide-angle
:class:`Camera`, a differential-drive :class:`Robot` with noisy :class:`OdometryNoise`,
:func:`render` (image and :class:`FrameTruth`), :func:`simulate_run` (a whole :class:`Run`),
datasets (:func:`write_dataset`), the calibration scene (:func:`render_calibration`) and true
occupancy rasters (:class:`OccupancyRaster`). Everything is deterministic per seed.

>>> from floorscan.sim import World, Camera, render
>>> image, truth = render(World.builtin("corridor"), Camera(), (1.0, 0.0, 0.0))
>>> image.shape, sorted(set(truth.status_names))
((240, 320), ['boundary', 'no_boundary'])
"""

from .calibration import PATTERN_KINDS, CalibrationPattern, render_calibration
from .camera import Camera, Imaging
from .export import write_dataset
from .occupancy import FREE, OCCUPIED, UNKNOWN, OccupancyRaster
from .render import PIXEL_LABELS, FrameTruth, render, render_image
from .robot import OdometryNoise, Robot, Trajectory
from .run import Run, RunTruth, simulate_run
from .world import World

__all__ = [
    "FREE",
    "OCCUPIED",
    "PATTERN_KINDS",
    "PIXEL_LABELS",
    "UNKNOWN",
    "CalibrationPattern",
    "Camera",
    "FrameTruth",
    "Imaging",
    "OccupancyRaster",
    "OdometryNoise",
    "Robot",
    "Run",
    "RunTruth",
    "Trajectory",
    "World",
    "render",
    "render_calibration",
    "render_image",
    "simulate_run",
    "write_dataset",
]
