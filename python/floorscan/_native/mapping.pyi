"""
Mapping: the global grid, the local map, evidence merges, log-odds.
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

def check_slam_options(options: Any) -> Any:
    """
    Reads `SlamOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
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
