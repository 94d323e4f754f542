"""
The simulator: worlds, cameras, rendering with truth, robot runs, calibration scenes.
"""

from .ranging import GroundTable
from _typeshed import Incomplete
from typing import Any, SupportsFloat, SupportsIndex, final

@final
class SimCamera:
    """
    A camera with its per-pixel rays.
    """
    @staticmethod
    def default_json(width: SupportsIndex, height: SupportsIndex) -> str:
        """
        The default wide-angle camera at a resolution, as JSON.
        """
    @staticmethod
    def from_json(text: str) -> SimCamera: ...
    def ground_table(self, /, spacing_px: SupportsIndex, max_range_m: SupportsFloat | SupportsIndex) -> GroundTable:
        """
        The exact ground table of the camera.
        """
    def ground_to_pixel(self, /, x: Incomplete, y: Incomplete) -> tuple[Incomplete, Incomplete]:
        """
        Pixels (u, v) where ground points (camera ground frame) appear; NaN where not seen.
        """
    def pixel_to_ground(self, /, u: Incomplete, v: Incomplete, max_range_m: SupportsFloat | SupportsIndex) -> tuple[Incomplete, Incomplete]:
        """
        Exact ground points (camera ground frame) of pixels: two float64 arrays, NaN where none.
        """
    def to_json(self, /) -> str: ...

@final
class SimTruth:
    """
    Ground truth of rendered frames (kept native; converted to arrays or CSV on demand).
    """
    def __len__(self, /) -> int: ...
    def arrays(self, /) -> dict:
        """
        The truth as a dict of numpy arrays, shapes (N, W) or (N, W, 2) or (N, 3).
        """
    def to_csv(self, /, timestamps: Incomplete) -> str:
        """
        The truth columns CSV (header included) with the frames' timestamps [s].
        """

@final
class SimWorld:
    """
    A world prepared for rendering.
    """
    @property
    def bounds(self, /) -> tuple[float, float, float, float]:
        """
        (xmin, ymin, xmax, ymax) [m].
        """
    @staticmethod
    def builtin(name: str) -> SimWorld: ...
    @staticmethod
    def builtin_names() -> list[str]: ...
    @property
    def ceiling_m(self, /) -> float: ...
    @property
    def description(self, /) -> str: ...
    @staticmethod
    def from_toml(text: str, source_name: str) -> SimWorld:
        """
        Parses a world file's text; `source_name` (a path) prefixes error messages.
        """
    @property
    def name(self, /) -> str: ...
    def occupancy(self, /, options_json: str) -> tuple[Any, float, float]:
        """
        True occupancy raster: (cells (H, W) int8 with 100/0/-1, row 0 = lowest y; origin x, y).
        """
    @property
    def source(self, /) -> str | None: ...
    @property
    def start(self, /) -> tuple[float, float, float]:
        """
        (x, y, yaw) of the start pose.
        """
    def to_json(self, /) -> str:
        """
        The world as JSON (the simulator's serde form; for inspection).
        """
    @property
    def tour(self, /) -> list[tuple[float, float]]: ...

def sim_default_pattern(camera: SimCamera, kind: str) -> str:
    """
    The default pattern of a kind ("checkerboard" or "lines") in front of a camera, as JSON.
    """

def sim_drive(x: SupportsFloat | SupportsIndex, y: SupportsFloat | SupportsIndex, yaw: SupportsFloat | SupportsIndex, motion_json: str, robot_json: str, noise_json: str, duration_s: SupportsFloat | SupportsIndex, seed: SupportsIndex) -> tuple[Any, Any, Any]:
    """
    Drives the robot: (times (N,), truth (N, 3), odometry (N, 3)).
    """

def sim_pattern_points(pattern_json: str) -> Any:
    """
    Pattern points (inner corners or crossings; camera ground frame), (M, 2).
    """

def sim_render(world: SimWorld, camera: SimCamera, x: SupportsFloat | SupportsIndex, y: SupportsFloat | SupportsIndex, yaw: SupportsFloat | SupportsIndex, seed: SupportsIndex, frame: SupportsIndex, truth: bool, max_range_m: SupportsFloat | SupportsIndex) -> tuple[Any, Any, SimTruth | None, float]:
    """
    Renders one view: (image (H, W) uint8, labels (H, W) uint8, truth or None, exposure).
    """

def sim_render_calibration(camera: SimCamera, pattern_json: str, seed: SupportsIndex) -> tuple[Any, Any]:
    """
    Renders the calibration scene of a pattern (JSON): (image, labels).
    """

def sim_render_run(world: SimWorld, camera: SimCamera, poses: Incomplete, seed: SupportsIndex, labels: bool, truth: bool, max_range_m: SupportsFloat | SupportsIndex, threads: SupportsIndex) -> tuple[Any, Any | None, SimTruth | None, Any]:
    """
    Renders frames at poses (N, 3): (images (N, H, W), labels or None, truth or None,
    exposures (N,)). The GIL is released for the whole run.
    """

def validate_camera(options_json: str) -> None:
    """
    Validates a camera (JSON, the simulator's serde form).
    """

def validate_imaging(options_json: str) -> None:
    """
    Validates imaging options (JSON, the simulator's serde form).
    """

def validate_occupancy_options(options_json: str) -> None:
    """
    Validates occupancy raster options (JSON, the simulator's serde form).
    """

def validate_odometry_noise(options_json: str) -> None:
    """
    Validates odometry noise (JSON, the simulator's serde form).
    """

def validate_pattern(pattern_json: str) -> None:
    """
    Validates a pattern (JSON, the simulator's serde form).
    """

def validate_robot_options(options_json: str) -> None:
    """
    Validates robot options (JSON, the simulator's serde form).
    """

def __getattr__(name: str) -> Incomplete: ...
