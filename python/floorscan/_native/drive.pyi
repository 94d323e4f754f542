"""
Driving: the avoidance map's updates, the planner's navigation function, the scan
matcher's search, hit map and match information.
"""

from _typeshed import Incomplete, SupportsLenAndGetItem
from typing import Any, SupportsFloat, SupportsIndex, final

@final
class AvoidanceMap:
    """
    The avoidance map's insertion machinery for a `side` x `side` window of `cell_size_m`
    [m] cells clamped to `clamp_nats` (min < 0 < max); its scratch layers are made once.
    """
    def __new__(cls, /, side: SupportsIndex, cell_size_m: SupportsFloat | SupportsIndex, clamp_nats: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex]) -> AvoidanceMap: ...
    def insert_laser(self, /, log_odds: Incomplete, plan_log_odds: Incomplete, sensor_cell: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex], end_cells: Incomplete, returned: Incomplete, hit_nats: SupportsFloat | SupportsIndex, miss_nats: SupportsFloat | SupportsIndex) -> None:
        """
        Adds an ideal 2-D laser scan to `log_odds` and to the planner's `plan_log_odds` (in
        place): the fan from the sensor at `sensor_cell` to the beam ends `end_cells` (N, 2)
        [fractional cells of the window] gets `miss_nats`, the end cells where `returned` (N,)
        bool get `hit_nats`.
        """
    def insert_visual(self, /, log_odds: Incomplete, confirmed: Incomplete, plan_log_odds: Incomplete, plan_confirmed: Incomplete, plan_near_hits: Incomplete, origin_cells: tuple[SupportsIndex, SupportsIndex], camera: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], status: Incomplete, x: Incomplete, y: Incomplete, near_x: Incomplete, near_y: Incomplete, footprints: Incomplete, errors: Incomplete, model: Any) -> None:
        """
        Adds one visual scan to `log_odds` ((side, side) float32, in place; its cell (0, 0) is
        world cell `origin_cells`) and to `confirmed` ((side, side) uint8, in place: the cells a
        hit from `confirm_range_m` or farther confirmed), and to the planner's layers
        `plan_log_odds` and `plan_confirmed`, whose confirmed obstacles alone clear by the
        model's `confirmed_clearing` (`log_odds` clear in full), and which take a hit nearer
        than the model's `persist_range_m` only when it persists (`plan_near_hits`, (side,
        side) uint8, in place: the cells the last insertion hit from that near), seen by the
        camera at
        `camera` (world_from_camera): per column the status codes, boundary points, near edges
        [m, camera ground frame], footprints and predicted errors [m] (NaN: none); `model` a
        `floorscan.drive.VisualSensorModel` (its fields are read by name).
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

def decay(values: Incomplete, factor: SupportsFloat | SupportsIndex) -> None:
    """
    Forgetting: every value of `values` (float32, in place) times `factor`.
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
