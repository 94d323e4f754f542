"""
Driving: the avoidance map, the planner's navigation function and dynamic window, the
drive's options.
"""

from _typeshed import Incomplete, SupportsLenAndGetItem
from typing import Any, SupportsFloat, SupportsIndex, final

@final
class AvoidanceMap:
    """
    The avoidance map of `options` (a dict of `AvoidanceMapOptions`' fields) whose window is
    centred near `center` [m, odometry frame].
    """
    def __new__(cls, /, options: Any, center: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex]) -> AvoidanceMap: ...
    @property
    def bumps(self, /) -> Incomplete:
        """
        The bumper's marks (side, side) float32 (a copy).
        """
    @bumps.setter
    def bumps(self, /, value: Incomplete) -> None: ...
    @property
    def confirmed(self, /) -> Incomplete:
        """
        1 where a hit from `confirm_range_m` or farther confirmed the cell (a copy).
        """
    @confirmed.setter
    def confirmed(self, /, value: Incomplete) -> None: ...
    def decay(self, /, dt_s: SupportsFloat | SupportsIndex) -> None:
        """
        Forgets `dt_s` [s] of evidence and bumps (their half-lives).
        """
    def insert_laser(self, /, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], ranges: Incomplete, angles: Incomplete, range_max_m: SupportsFloat | SupportsIndex, hit_nats: SupportsFloat | SupportsIndex | None = None, miss_nats: SupportsFloat | SupportsIndex | None = None) -> None:
        """
        An ideal 2-D laser scan from `pose` (world_from_robot): `ranges` [m] (REP 117) at
        `angles` [rad, robot frame], free to each return or `range_max_m`, `hit_nats` at the
        return, `miss_nats` along the beam (None: the ideal laser's 2.2 / -2.0).
        """
    def insert_visual(self, /, camera: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], status: Incomplete, x: Incomplete, y: Incomplete, near_x: Incomplete, near_y: Incomplete, footprints: Incomplete, errors: Incomplete, model: Any) -> None:
        """
        Adds one visual scan seen by the camera at `camera` (world_from_camera, odometry
        frame): per column the status codes, boundary points, near edges [m, camera ground
        frame], footprints and predicted errors [m] (NaN: none); `model` a
        `floorscan.drive.VisualSensorModel` (its fields are read by name).
        """
    def known(self, /) -> Incomplete:
        """
        Cells the planner has evidence for (side, side) bool.
        """
    @property
    def log_odds(self, /) -> Incomplete:
        """
        The map's log odds (side, side) float32, row 0 = lowest y (a copy).
        """
    @log_odds.setter
    def log_odds(self, /, value: Incomplete) -> None: ...
    def mark_bump(self, /, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], bearing_rad: SupportsFloat | SupportsIndex, distance_m: SupportsFloat | SupportsIndex) -> None:
        """
        A bumper contact at `distance_m` along `bearing_rad` (robot frame) from `pose`.
        """
    def occupancy_classes(self, /) -> Incomplete:
        """
        The planner's classes (side, side) uint8: 0 free, 1 unknown, 2 occupied.
        """
    def occupied(self, /) -> Incomplete:
        """
        The planner's obstacles (side, side) bool (its evidence or the bumper's marks).
        """
    @property
    def origin_cells(self, /) -> tuple[int, int]:
        """
        The world cell of the window's cell (0, 0).
        """
    @property
    def plan_confirmed(self, /) -> Incomplete:
        """
        The planner's confirmed obstacles (a copy).
        """
    @plan_confirmed.setter
    def plan_confirmed(self, /, value: Incomplete) -> None: ...
    @property
    def plan_log_odds(self, /) -> Incomplete:
        """
        The planner's log odds (a copy).
        """
    @plan_log_odds.setter
    def plan_log_odds(self, /, value: Incomplete) -> None: ...
    @property
    def plan_near_hits(self, /) -> Incomplete:
        """
        The cells the last visual insertion hit from nearer than `persist_range_m` (a copy).
        """
    @plan_near_hits.setter
    def plan_near_hits(self, /, value: Incomplete) -> None: ...
    def probabilities(self, /) -> Incomplete:
        """
        Calibrated occupancy probabilities (side, side) float64; 0.5 without evidence.
        """
    def recenter(self, /, x: SupportsFloat | SupportsIndex, y: SupportsFloat | SupportsIndex) -> None:
        """
        Scrolls by whole cells so (x, y) [m] lies within a quarter window of the centre.
        """
    @property
    def side(self, /) -> int:
        """
        Cells on a side of the window.
        """

def avoidance_map_options_schema() -> Any:
    """
    The JSON schema of `AvoidanceMapOptions`: field docs, types, defaults.
    """

def best_velocity_sample(pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], vs: Incomplete, omegas: Incomplete, times_s: Incomplete, cost: Incomplete, origin_m: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], cell_m: SupportsFloat | SupportsIndex, unknown: Incomplete | None, nav: Incomplete, nav_origin_m: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], nav_cell_m: SupportsFloat | SupportsIndex, goal: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], scoring: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], inscribed: SupportsIndex) -> int | None:
    """
    The index `k = iw * len(vs) + iv` of the dynamic window's chosen sample of `vs` (float64
    [m/s]) x `omegas` (float64 [rad/s]) rolled out from `pose` (x, y, yaw) at `times_s`
    (float64 [s]), or None when no sample is admissible (`floorscan_core::dynamic_window`).
    `cost` (H, W) uint8 and `unknown` (H, W) bool share `origin_m` and `cell_m`; `nav` (h, w)
    float64 [m] has its own `nav_origin_m` and `nav_cell_m`; `scoring` is (path_distance_bias,
    goal_distance_bias, occdist_scale, forward_point_distance_m, blind_radius_m); costs from
    `inscribed` up are not admissible.
    """

def check_avoidance_map_options(options: Any) -> Any:
    """
    Reads `AvoidanceMapOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_costmap_options(options: Any) -> Any:
    """
    Reads `CostmapOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_drive_map_options(options: Any) -> Any:
    """
    Reads `DriveMapOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_drive_run_options(options: Any) -> Any:
    """
    Reads `DriveRunOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_dwa_options(options: Any) -> Any:
    """
    Reads `DwaOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_visual_sensor_model(options: Any) -> Any:
    """
    Reads `VisualModel` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def coarse_grid(cost: Incomplete, factor: SupportsIndex, blocked_from: SupportsIndex, unknown_cost: SupportsFloat | SupportsIndex, known: Incomplete | None = None) -> tuple[Incomplete, Incomplete]:
    """
    The navigation function's coarse grid from a costmap `cost` (H, W) uint8 in blocks of
    `factor` x `factor` cells: (blocked (h, w) bool: every cell of the block costs
    `blocked_from` or more; weight (h, w) float64: 1 + min(mean cost, blocked_from) / 64, plus
    `unknown_cost` times the block's share of cells not `known` (H, W) bool when given).
    """

def costmap_options_schema() -> Any:
    """
    The JSON schema of `CostmapOptions`: field docs, types, defaults.
    """

def default_avoidance_map_options() -> Any:
    """
    The default `AvoidanceMapOptions` (its serde form, a dict).
    """

def default_costmap_options() -> Any:
    """
    The default `CostmapOptions` (its serde form, a dict).
    """

def default_drive_map_options() -> Any:
    """
    The default `DriveMapOptions` (its serde form, a dict).
    """

def default_drive_run_options() -> Any:
    """
    The default `DriveRunOptions` (its serde form, a dict).
    """

def default_dwa_options() -> Any:
    """
    The default `DwaOptions` (its serde form, a dict).
    """

def default_visual_sensor_model() -> Any:
    """
    The default `VisualModel` (its serde form, a dict).
    """

def drive_map_options_schema() -> Any:
    """
    The JSON schema of `DriveMapOptions`: field docs, types, defaults.
    """

def drive_run_options_schema() -> Any:
    """
    The JSON schema of `DriveRunOptions`: field docs, types, defaults.
    """

def dwa_options_schema() -> Any:
    """
    The JSON schema of `DwaOptions`: field docs, types, defaults.
    """

def geodesic_distances(blocked: Incomplete, weight: Incomplete, seed_cells: Incomplete, seed_costs: Incomplete, step_m: SupportsFloat | SupportsIndex) -> Incomplete:
    """
    Geodesic cost-to-goal (H, W) float64 [m, weighted] over an 8-connected grid: `blocked`
    (H, W) bool cells are never entered, a step costs its length (`step_m` or sqrt 2 times it)
    times the mean `weight` (H, W) float64 of its two cells; `seed_cells` (K,) int64 row-major
    cell indices start at `seed_costs` (K,) float64. `inf` where nothing reaches.
    """

def visual_sensor_model_schema() -> Any:
    """
    The JSON schema of `VisualModel`: field docs, types, defaults.
    """

def __getattr__(name: str) -> Incomplete: ...
