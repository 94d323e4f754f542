"""
Ranging: ground tables, the edge and appearance rangers, scans.
"""

from _typeshed import Incomplete
from typing import Any, Final, SupportsFloat, SupportsIndex, final

SCAN_CSV_HEADER: Final[str]
"""
The scans CSV header (`floorscan_core::scan::SCAN_CSV_HEADER`).
"""

@final
class AppearanceRanger:
    def __new__(cls, /, table: GroundTable, options: Any) -> AppearanceRanger: ...
    def boundary_samples(self, /) -> Incomplete:
        """
        Per sampled column of the last scan, the packed bins of the pixels of the run that
        made its boundary: (columns, BOUNDARY_SAMPLES) uint32, NO_SAMPLE (2**32 - 1) where none.
        """
    @property
    def columns(self, /) -> Incomplete: ...
    @property
    def driven_floor_borders(self, /) -> Incomplete:
        """
        Per sampled column of the last scan: the row [px] of the first border between the
        reference's floor and driven-over floor (NaN where none; float64 array).
        """
    @property
    def driven_floor_columns(self, /) -> Incomplete:
        """
        Per sampled column of the last scan: whether it crossed floor known only as floor the
        robot drove over (bool array).
        """
    @property
    def frames_learned(self, /) -> int:
        """
        Frames learned since the last reset.
        """
    def learn_driven_floor(self, /, samples: Incomplete) -> int:
        """
        Learns packed samples of boundaries driven through as floor (from the next frame);
        returns how many were learned (NO_SAMPLE entries are skipped).
        """
    @property
    def options(self, /) -> Any:
        """
        The options (every field, serde form).
        """
    def reset_model(self, /) -> None:
        """
        Forgets the learned floor.
        """
    def scan(self, /, image: Any, timestamp: SupportsFloat | SupportsIndex) -> Scan:
        """
        Learns from the frame's reference band and scans it: a (H, W) grey or C-contiguous
        (H, W, 3) RGB array of uint8 or uint16; the GIL is released while scanning.
        """

@final
class FloorParallax:
    def __new__(cls, /, table: GroundTable, options: Any) -> FloorParallax: ...
    @property
    def options(self, /) -> Any:
        """
        The options (every field, serde form).
        """
    def reset(self, /) -> None:
        """
        Forgets the earlier frames.
        """
    def scan(self, /, ranger: VisualRanger, image: Any, timestamp: SupportsFloat | SupportsIndex, world_from_camera: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex] | None = None) -> tuple[Scan, tuple[float, int, float]]:
        """
        Ranges a (H, W) uint8 or uint16 image with `ranger` and checks its boundaries against
        the earlier frames when `world_from_camera` (x, y, yaw) is given; returns the scan and
        the report `(baseline_m, vetoes, noise_grey)`. The GIL is released meanwhile.
        """

@final
class GroundTable:
    def __eq__(self, other: object, /) -> bool: ...
    @staticmethod
    def from_arrays(image_width: SupportsIndex, image_height: SupportsIndex, spacing_px: SupportsIndex, x_m: Incomplete, y_m: Incomplete) -> GroundTable: ...
    @staticmethod
    def from_camera(lens: Any, mount: Any, image_width: SupportsIndex, image_height: SupportsIndex, spacing_px: SupportsIndex, max_range_m: SupportsFloat | SupportsIndex) -> GroundTable: ...
    @staticmethod
    def from_json(text: str) -> GroundTable: ...
    @property
    def image_height(self, /) -> int: ...
    @property
    def image_width(self, /) -> int: ...
    def lookup(self, /, u: Incomplete, v: Incomplete) -> tuple[Incomplete, Incomplete]:
        """
        Ground points at pixels (u, v): two float64 arrays, NaN where there is no ground.
        """
    def lookup_error(self, /, u: Incomplete, v: Incomplete) -> Incomplete:
        """
        Predicted errors [m] at pixels (u, v), NaN where unknown or no ground.
        """
    def metadata(self, /) -> Any:
        """
        The free-form metadata (a dict).
        """
    def node_arrays(self, /) -> tuple[Incomplete, Incomplete]:
        """
        Node values as two (nodes_v, nodes_u) float64 arrays, NaN for no ground.
        """
    def node_errors(self, /) -> Incomplete | None:
        """
        Node errors as a (nodes_v, nodes_u) float64 array [m], NaN unknown; None if the table
        carries none.
        """
    @property
    def spacing_px(self, /) -> int: ...
    def to_json(self, /) -> str: ...
    def with_errors(self, /, errors_m: Incomplete) -> GroundTable:
        """
        A copy carrying a predicted floor-position error [m] per node (row-major; NaN unknown).
        """
    def with_metadata(self, /, metadata: Any) -> GroundTable:
        """
        A copy of the table with `metadata` (a dict of JSON values) replacing its metadata.
        """

@final
class Scan:
    def __len__(self, /) -> int: ...
    @property
    def bearings(self, /) -> Incomplete: ...
    @property
    def columns(self, /) -> Incomplete: ...
    @property
    def confidence(self, /) -> Incomplete:
        """
        Each reading's confidence in [0, 1].
        """
    def csv_lines(self, /) -> str:
        """
        The scan's CSV lines (no header), see `floorscan_core::scan::SCAN_CSV_HEADER`.
        """
    @property
    def footprints(self, /) -> Incomplete:
        """
        Floor length one pixel row covers at each boundary [m] (0 where not a boundary).
        """
    @staticmethod
    def from_arrays(timestamp_s: SupportsFloat | SupportsIndex, columns: Incomplete, rows: Incomplete, status: Incomplete, x_m: Incomplete, y_m: Incomplete, near_x_m: Incomplete, near_y_m: Incomplete) -> Scan:
        """
        Rebuilds a scan from its CSV columns (status codes as in `ColumnStatus.code`). The near
        edge of the field of view is not part of the CSV; pass it if known (NaN otherwise).
        """
    @property
    def near_x(self, /) -> Incomplete: ...
    @property
    def near_y(self, /) -> Incomplete: ...
    @property
    def ranges(self, /) -> Incomplete: ...
    @property
    def rows(self, /) -> Incomplete: ...
    @property
    def start_rows(self, /) -> Incomplete: ...
    @property
    def status_codes(self, /) -> Incomplete: ...
    @property
    def timestamp(self, /) -> float: ...
    def to_laser_bins(self, /, angle_min: SupportsFloat | SupportsIndex, angle_max: SupportsFloat | SupportsIndex, angle_increment: SupportsFloat | SupportsIndex) -> dict:
        """
        Fixed angular binning (sensor_msgs/LaserScan fields) as a dict.
        """
    @property
    def x(self, /) -> Incomplete: ...
    @property
    def y(self, /) -> Incomplete: ...

@final
class VisualRanger:
    def __new__(cls, /, table: GroundTable, options: Any) -> VisualRanger: ...
    @property
    def columns(self, /) -> Incomplete:
        """
        The sampled image columns, in output order.
        """
    @property
    def options(self, /) -> Any:
        """
        The options (every field, serde form).
        """
    def scan(self, /, image: Any, timestamp: SupportsFloat | SupportsIndex) -> Scan:
        """
        Scans a (H, W) uint8 or uint16 image; the GIL is released while scanning.
        """
    @property
    def table(self, /) -> GroundTable: ...

def appearance_options_schema() -> Any:
    """
    The JSON schema of `AppearanceOptions`: field docs, types, defaults.
    """

def check_appearance_options(options: Any) -> Any:
    """
    Reads `AppearanceOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_fusion_options(options: Any) -> Any:
    """
    Reads `FusionOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_parallax_options(options: Any) -> Any:
    """
    Reads `ParallaxOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def check_ranger_options(options: Any) -> Any:
    """
    Reads `RangerOptions` from a dict of any of its fields (the others take their defaults), validates it and returns every field.
    """

def column_statuses() -> list[tuple[str, int]]:
    """
    Every column status as (name, code), in code order (`floorscan.ColumnStatus` is built
    from it).
    """

def default_appearance_options() -> Any:
    """
    The default `AppearanceOptions` (its serde form, a dict).
    """

def default_fusion_options() -> Any:
    """
    The default `FusionOptions` (its serde form, a dict).
    """

def default_parallax_options() -> Any:
    """
    The default `ParallaxOptions` (its serde form, a dict).
    """

def default_ranger_options() -> Any:
    """
    The default `RangerOptions` (its serde form, a dict).
    """

def fuse(edge: Scan, appearance: Scan, options: Any, image_height: SupportsIndex, previous_textured: bool = False, frames_inherited: SupportsIndex = 0, driven_floor: Incomplete | None = None) -> tuple[Scan, bool, int]:
    """
    Fuses an edge scan and an appearance scan of the same frame and columns
    (`floorscan_core::fusion`) of an image `image_height` rows tall, with `options` (a dict
    of `FusionOptions` fields, the others at their defaults), after frames whose floor was
    judged textured or not (`previous_textured`, inherited `frames_inherited` frames in a row);
    returns the fused scan and the judgement after this frame, `(scan, textured,
    frames_inherited)`. `driven_floor`: the appearance ranger's `driven_floor_borders` (an edge
    on such a border is the border of floor driven over, not an obstacle).
    """

def fusion_options_schema() -> Any:
    """
    The JSON schema of `FusionOptions`: field docs, types, defaults.
    """

def parallax_options_schema() -> Any:
    """
    The JSON schema of `ParallaxOptions`: field docs, types, defaults.
    """

def ranger_options_schema() -> Any:
    """
    The JSON schema of `RangerOptions`: field docs, types, defaults.
    """

def __getattr__(name: str) -> Incomplete: ...
