"""
Mapping: the global grid, the local map, evidence merges, log-odds, the correlative scan
matcher (its search, its match's information) and SLAM's options.
"""

from .ranging import Scan
from _typeshed import Incomplete, SupportsGetItem, SupportsLenAndGetItem
from typing import Any, Final, SupportsFloat, SupportsIndex, final

FIELD_REUSE_M: Final[float]
"""
How far [m] the pose graph's rolling submap field may be used from where it was built
(`floorscan_core::pose_graph_options::FIELD_REUSE_M`).
"""

MAX_ABS_UNITS: Final[int]
"""
Largest stored log-odds magnitude (`floorscan_core::log_odds::MAX_ABS_UNITS`).
"""

UNITS_PER_NAT: Final[float]
"""
Stored log-odds units per nat (`floorscan_core::log_odds::UNITS_PER_NAT`).
"""

@final
class LocalMap:
    def __new__(cls, /, options: Any, inserter_options: Any, local_from_robot: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> LocalMap: ...
    @property
    def cell_size_m(self, /) -> float: ...
    def distances(self, /, xs: Incomplete, ys: Incomplete, max_m: SupportsFloat | SupportsIndex) -> Incomplete: ...
    def extent(self, /) -> tuple[int, int, int, int]:
        """
        The window (min x, min y, width, height) [cells of the local lattice].
        """
    def insert_laser(self, /, ranges: Incomplete, angles: Incomplete | None, angle_min: SupportsFloat | SupportsIndex, angle_increment: SupportsFloat | SupportsIndex, range_min: SupportsFloat | SupportsIndex, range_max: SupportsFloat | SupportsIndex, mount: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[int, int, int]: ...
    def insert_scan(self, /, scan: Scan, mount: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[int, int, int]: ...
    def insert_sonar(self, /, ranges: Incomplete, mounts: Incomplete, beam_width: SupportsFloat | SupportsIndex, range_max: SupportsFloat | SupportsIndex) -> tuple[int, int, int]: ...
    def limits(self, /) -> tuple[int, int, int, int]: ...
    def move_by(self, /, delta: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> None: ...
    def move_to(self, /, local_from_robot: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> None: ...
    def occupancy_codes(self, /, xs: Incomplete, ys: Incomplete) -> Incomplete: ...
    @property
    def options(self, /) -> Any:
        """
        The options (every field, serde form).
        """
    @property
    def origin_m(self, /) -> tuple[float, float]: ...
    @property
    def pose(self, /) -> tuple[float, float, float]: ...
    def robot_view(self, /, width: SupportsIndex, height: SupportsIndex) -> Incomplete:
        """
        The window resampled in the robot frame: (height, width) int16, row 0 at the robot's
        right (most negative y), column 0 behind it (most negative x).
        """
    def values(self, /, min_x: SupportsIndex, min_y: SupportsIndex, width: SupportsIndex, height: SupportsIndex) -> Incomplete: ...

@final
class OccupancyGrid:
    def __new__(cls, /, grid_options: Any, inserter_options: Any) -> OccupancyGrid: ...
    @property
    def allocated_tiles(self, /) -> int: ...
    @property
    def cell_size_m(self, /) -> float: ...
    def copy(self, /) -> OccupancyGrid: ...
    def distances(self, /, xs: Incomplete, ys: Incomplete, max_m: SupportsFloat | SupportsIndex) -> Incomplete: ...
    def evidence_extent(self, /) -> tuple[int, int, int, int] | None:
        """
        (min x, min y, width, height) [cells] of the non-zero evidence, None if there is none.
        """
    def evidence_values(self, /, min_x: SupportsIndex, min_y: SupportsIndex, width: SupportsIndex, height: SupportsIndex) -> Incomplete:
        """
        The evidence of a rectangle as an (H, W) int32 array [1/1000 nat], row 0 the lowest y.
        """
    def extent(self, /) -> tuple[int, int, int, int]:
        """
        The exported rectangle (min x, min y, width, height) [cells].
        """
    @property
    def fixed_cells(self, /) -> tuple[int, int, int, int] | None:
        """
        Fixed bounds (min x, min y, max x, max y) [cells, max excluded], None if growing.
        """
    @property
    def grid_memory_bytes(self, /) -> int: ...
    @property
    def grid_options(self, /) -> Any:
        """
        The grid options (every field, serde form).
        """
    def insert_laser(self, /, ranges: Incomplete, angles: Incomplete | None, angle_min: SupportsFloat | SupportsIndex, angle_increment: SupportsFloat | SupportsIndex, range_min: SupportsFloat | SupportsIndex, range_max: SupportsFloat | SupportsIndex, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], mount: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[int, int, int]: ...
    def insert_lasers(self, /, ranges: Incomplete, poses: Incomplete, angles: Incomplete | None, angle_min: SupportsFloat | SupportsIndex, angle_increment: SupportsFloat | SupportsIndex, range_min: SupportsFloat | SupportsIndex, range_max: SupportsFloat | SupportsIndex, mount: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[int, int, int]:
        """
        N scans of B beams: ranges (N, B), poses (N, 3). The GIL is released.
        """
    def insert_rays(self, /, starts: Incomplete, ends: Incomplete, hits: Incomplete, hit_nats: SupportsFloat | SupportsIndex, miss_nats: SupportsFloat | SupportsIndex) -> tuple[int, int, int]:
        """
        One batch of world rays: starts (N, 2), ends (N, 2), hits (N,). GIL released.
        """
    def insert_scan(self, /, scan: Scan, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], mount: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[int, int, int]: ...
    def insert_sonar(self, /, ranges: Incomplete, mounts: Incomplete, beam_width: SupportsFloat | SupportsIndex, range_max: SupportsFloat | SupportsIndex, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[int, int, int]: ...
    @property
    def inserter_options(self, /) -> Any:
        """
        The inserter options (every field, serde form).
        """
    def keep_evidence(self, /) -> None:
        """
        Starts keeping the unclamped evidence layer (before the first update).
        """
    @property
    def keeps_evidence(self, /) -> bool: ...
    def limits(self, /) -> tuple[int, int, int, int]:
        """
        (clamp_min, clamp_max, occupied_at, free_at) in stored units (1/1000 nat).
        """
    @property
    def memory_bytes(self, /) -> int: ...
    def occupancy_codes(self, /, xs: Incomplete, ys: Incomplete) -> Incomplete: ...
    @property
    def origin_m(self, /) -> tuple[float, float]: ...
    def values(self, /, min_x: SupportsIndex, min_y: SupportsIndex, width: SupportsIndex, height: SupportsIndex) -> Incomplete: ...
    def write_values(self, /, min_x: SupportsIndex, min_y: SupportsIndex, array: Incomplete) -> None:
        """
        Writes an (H, W) int16 array of raw values with its first cell at (min_x, min_y).
        """

@final
class ScanMatcher:
    """
    The matcher of `options` (a dict of `ScanMatcherOptions`' fields) whose map is centred on
    `center` [m, world frame].
    """
    def __new__(cls, /, options: Any, center: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex]) -> ScanMatcher: ...
    @property
    def calibration(self, /) -> tuple[float, float]:
        """
        Odometry's estimated errors: (turn scale error, heading drift [rad/m]).
        """
    @calibration.setter
    def calibration(self, /, value: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex]) -> None: ...
    def correct(self, /, points: Incomplete, prior: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[tuple[float, float, float], float, bool, int]:
        """
        One frame: `points` (N, 2) float64 [m, robot frame] matched near the odometry pose
        `prior` (world_from_robot) after the filter's prediction, fused with it, the new points
        stored; ((x, y, yaw), score, accepted, points).
        """
    @property
    def covariance(self, /) -> Incomplete:
        """
        The covariance (5, 5) of the state's error: x [m], y [m], yaw [rad], the turn scale
        error, the heading drift [rad/m].
        """
    @covariance.setter
    def covariance(self, /, value: Incomplete) -> None: ...
    def cover(self, /, x: SupportsFloat | SupportsIndex, y: SupportsFloat | SupportsIndex, half_m: SupportsFloat | SupportsIndex) -> tuple[Incomplete, int, int]:
        """
        Makes the kept field cover the square of half-side `half_m` around (x, y); returns it.
        """
    @property
    def field(self, /) -> tuple[Incomplete, int, int] | None:
        """
        The likelihood field kept (a copy) or None.
        """
    def field_around(self, /, x: SupportsFloat | SupportsIndex, y: SupportsFloat | SupportsIndex, half_m: SupportsFloat | SupportsIndex) -> tuple[Incomplete, int, int]:
        """
        A fresh likelihood field over the square of half-side `half_m` [m] around (x, y).
        """
    @property
    def frames(self, /) -> int:
        """
        Scans stored so far.
        """
    def fuse(self, /, found: tuple[tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex], SupportsFloat | SupportsIndex, bool, SupportsIndex], prior: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], information: Incomplete) -> tuple[tuple[float, float, float], float, bool, int]:
        """
        The match `found` ((x, y, yaw), score, accepted, points) fused with the prediction
        `prior` with the match's `information` (3, 3) float64.
        """
    @property
    def hits(self, /) -> Incomplete:
        """
        The hit counts (side, side) uint8 (row 0 = lowest y), a copy.
        """
    def information(self, /, points: Incomplete, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> Incomplete:
        """
        The information matrix (3, 3) of the match of `points` at `pose` on the kept field.
        """
    def insert(self, /, points: Incomplete, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], novel_only: bool) -> int:
        """
        Stores `points` seen from `pose` (only those the map does not explain when
        `novel_only`); how many were stored.
        """
    @property
    def last_mahalanobis(self, /) -> float | None:
        """
        The last fused match's innovation as a Mahalanobis distance (None before any).
        """
    @property
    def last_pose(self, /) -> tuple[float, float, float] | None:
        """
        The pose kept last (world_from_robot), None before the first frame.
        """
    @last_pose.setter
    def last_pose(self, /, value: SupportsLenAndGetItem[SupportsFloat | SupportsIndex] | None) -> None: ...
    def match_scan(self, /, points: Incomplete, prior: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[tuple[float, float, float], float, bool, int]:
        """
        The best pose for `points` near `prior`, the map unchanged (no filter).
        """
    @property
    def origin_m(self, /) -> tuple[float, float]:
        """
        The grid's cell (0, 0)'s lower-left corner [m].
        """
    def predict(self, /, prior: SupportsLenAndGetItem[SupportsFloat | SupportsIndex]) -> tuple[float, float, float]:
        """
        The filter's prediction for odometry's `prior`.
        """
    @property
    def side(self, /) -> int:
        """
        Cells on a side of the grid.
        """

def check_grid_options(options: Any) -> Any:
    """
    Reads `GridOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_inserter_options(options: Any) -> Any:
    """
    Reads `InserterOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_local_map_options(options: Any) -> Any:
    """
    Reads `LocalMapOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_pose_graph_options(options: Any) -> Any:
    """
    Reads `PoseGraphOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_scan_matcher_options(options: Any) -> Any:
    """
    Reads `ScanMatcherOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_slam_options(options: Any) -> Any:
    """
    Reads `SlamOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def correlative_search(field: Incomplete, origin_m: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex], cell_m: SupportsFloat | SupportsIndex, points: Incomplete, prior: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], xy_steps: SupportsIndex, yaw_steps: SupportsIndex, yaw_step_rad: SupportsFloat | SupportsIndex, prior_xy_m: SupportsFloat | SupportsIndex, prior_yaw_rad: SupportsFloat | SupportsIndex) -> tuple[tuple[float, float, float], float, float]:
    """
    The best pose (x, y, yaw), its mean field value and its score for `points` (N, 2) float64
    [m, robot frame] around `prior` (world_from_robot): translations of -xy_steps..=xy_steps
    cells of `field` (H, W) float32 (values in [0, 1], row 0 = lowest y, cell (0, 0)'s corner
    at `origin_m`, cells `cell_m` wide), yaws of -yaw_steps..=yaw_steps times `yaw_step_rad`;
    score = mean field value x exp(-(|t| / prior_xy_m)^2 - (dyaw / prior_yaw_rad)^2); then
    refined below a cell on the field read bilinearly (`floorscan_core::correlative_search::refine`).
    """

def default_grid_options() -> Any:
    """
    The default `GridOptions` (its serde form, a dict).
    """

def default_inserter_options() -> Any:
    """
    The default `InserterOptions` (its serde form, a dict).
    """

def default_local_map_options() -> Any:
    """
    The default `LocalMapOptions` (its serde form, a dict).
    """

def default_pose_graph_options() -> Any:
    """
    The default `PoseGraphOptions` (its serde form, a dict).
    """

def default_scan_matcher_options() -> Any:
    """
    The default `ScanMatcherOptions` (its serde form, a dict).
    """

def default_slam_options() -> Any:
    """
    The default `SlamOptions` (its serde form, a dict).
    """

def grid_options_schema() -> Any:
    """
    The JSON schema of `GridOptions`: field docs, types, defaults.
    """

def inserter_options_schema() -> Any:
    """
    The JSON schema of `InserterOptions`: field docs, types, defaults.
    """

def local_map_options_schema() -> Any:
    """
    The JSON schema of `LocalMapOptions`: field docs, types, defaults.
    """

def match_information(field: Incomplete, origin_m: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex], cell_m: SupportsFloat | SupportsIndex, points: Incomplete, pose: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], yaw_step_rad: SupportsFloat | SupportsIndex) -> Incomplete:
    """
    The information matrix (3, 3) float64 of `points` (N, 2) float64 [m, robot frame] matched at
    `pose` (world_from_robot): minus the Hessian of the sum of `field` (H, W) float32 (row 0 =
    lowest y, cell (0, 0)'s corner at `origin_m`, cells `cell_m` wide) read bilinearly at the
    points over (x, y, yaw), by central differences of a cell and of `yaw_step_rad`, its
    negative eigenvalues cut to 0; a point whose four cells leave the field reads 0
    (`floorscan_core::match_information`).
    """

def merge_evidence(cell_sizes_m: SupportsGetItem[int, SupportsFloat | SupportsIndex], origins_m: SupportsGetItem[int, tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex]], arrays: SupportsGetItem[int, Incomplete]) -> tuple[tuple[float, float], Incomplete]:
    """
    Sums evidence maps on one cell lattice: `cell_sizes_m[k]`, `origins_m[k]` (corner of
    cell [0, 0]) and `arrays[k]` ((H, W) int32, row 0 the lowest y). Returns the merged
    origin and array.
    """

def occupancy_classes() -> list[tuple[str, int]]:
    """
    Every occupancy class as (name, code), in code order (`floorscan.Occupancy` is built from
    it).
    """

def pose_graph_field_half_side_m(options: Any) -> float:
    """
    `PoseGraphOptions::field_half_side_m` of a dict of its fields: the half-side [m] of a
    search's likelihood field around the pose searched from.
    """

def pose_graph_options_schema() -> Any:
    """
    The JSON schema of `PoseGraphOptions`: field docs, types, defaults.
    """

def probabilities_from_units(units: Incomplete) -> Incomplete:
    """
    Probabilities of stored log-odds values (any shape, int16 or int32 [1/1000 nat]) as
    float64: `1 / (1 + exp(-units / 1000))`.
    """

def scan_matcher_options_schema() -> Any:
    """
    The JSON schema of `ScanMatcherOptions`: field docs, types, defaults.
    """

def slam_options_schema() -> Any:
    """
    The JSON schema of `SlamOptions`: field docs, types, defaults.
    """

def units_from_probabilities(probabilities: Incomplete, lo: SupportsIndex, hi: SupportsIndex) -> Incomplete:
    """
    Stored log-odds units (int16, rounded, within +-`MAX_ABS_UNITS` and then `[lo, hi]`) of
    probabilities (any shape, float64 in [0, 1]; 0 and 1 go to the bounds, NaN to 0).
    """

def __getattr__(name: str) -> Incomplete: ...
