"""The one configuration file: every parameter of ranger, calibration, rig, map, sensors and
outputs, with documented defaults. ``floorscan config --default`` prints it; command-line flags
override it; unknown or ill-typed keys are errors that name the key.

Each table is the options of one component (field names and meanings as in the Python API and
the Rust options structs); values are checked again, for range, when the component is built.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Dict, Optional, Union, get_args, get_origin, get_type_hints

from .._atomic import PathLike, write_atomic
from ..calibration.options import CalibrationOptions
from ..errors import ConfigError
from ..formats.toml_file import dumps_toml, load_toml, loads_toml

_CAL = CalibrationOptions()


def doc(text: str, default: Any = dataclasses.MISSING, **kw):
    return field(default=default, metadata={"doc": text}, **kw)


@dataclass
class RangerConfig:
    kind: str = doc(
        "range sensor: edge (the paper's box filter) | appearance (floor colour and texture model) | fused (appearance boundaries placed by nearby edges)",
        "edge",
    )
    columns: int = doc("number of evenly spaced image columns sampled per frame", 64)
    half_width: int = doc("box filter half-width d [px], >= 1", 4)
    threshold: float = doc(
        "edge threshold on |R| of eq. (1)-(2) (half the difference of the window means), intensity units",
        10.0,
    )
    refine: str = doc(
        "boundary placement: subpixel | peak | none (the paper's first crossing)", "subpixel"
    )
    bottom_margin: int = doc(
        "rows skipped at the bottom of each column (bumper, dead rows) [px]", 2
    )
    max_range_m: Optional[float] = doc(
        "farthest range scanned [m]; inf: as far as the table has ground", 3.0
    )
    auto_threshold: bool = doc(
        "set the threshold from the first frame: auto_threshold_k x the carpet's texture noise near the robot (false: use `threshold`)",
        False,
    )
    auto_threshold_k: float = doc("multiple of the texture noise for the automatic threshold", 5.0)


@dataclass
class AppearanceConfig:
    reference_fraction: float = doc(
        "height of the reference band of floor above each column's start, share of the image height, (0, 0.5]",
        0.1,
    )
    features: str = doc("statistics compared: colour_texture | colour", "colour_texture")
    min_floor_share: float = doc(
        "a pixel is floor when this share of the reference lies within one histogram bin of it, (0, 1)",
        0.003,
    )
    intensity_reach: int = doc(
        "intensity bins (16 grey levels each) a pixel may lie from the reference and match, 1..15",
        1,
    )
    patch_half_width: int = doc("half-width of the patch classified around each column [px]", 2)
    min_run: int = doc("rows of not-floor in a run that make a boundary, >= 1", 3)
    adaptation_rate: float = doc("weight of the newest frame in the floor model, (0, 1]", 0.5)
    snap_rows: float = doc(
        "fused ranger: largest distance [rows] at which an edge replaces the appearance boundary",
        3.0,
    )


@dataclass
class CalibrationConfig:
    # Defaults from floorscan.calibration.CalibrationOptions (validated there when built).
    spacing_px: int = doc("ground table node spacing [px]", _CAL.spacing_px)
    coverage: str = doc(
        "nodes with ground: trusted (predicted error within max_error_fraction of the range) | "
        "pattern (around the pattern only) | all (wherever the fitted camera sees floor)",
        _CAL.coverage.value,
    )
    max_error_fraction: float = doc(
        "largest predicted floor error a trusted node may have, fraction of its range",
        _CAL.max_error_fraction,
    )
    min_error_m: float = doc(
        "a node whose predicted error is at most this [m] is trusted at any range",
        _CAL.min_error_m,
    )
    max_range_m: float = doc("no ground beyond this range [m]", _CAL.max_range_m)
    intrinsics: Optional[str] = doc(
        "known lens intrinsics (OpenCV FileStorage YAML/XML or ROS camera_info YAML): only the "
        "camera's pose is fitted; unset: the lens is fitted too",
        None,
    )
    extrapolate: bool = doc('older spelling of coverage = "all"', False)

    def kwargs(self) -> Dict[str, Any]:
        """The keyword options of :func:`floorscan.calibrate`."""
        return {
            "spacing_px": self.spacing_px,
            "coverage": "all" if self.extrapolate else self.coverage,
            "max_error_fraction": self.max_error_fraction,
            "min_error_m": self.min_error_m,
            "max_range_m": self.max_range_m,
            **({"intrinsics": self.intrinsics} if self.intrinsics else {}),
        }


@dataclass
class RigConfig:
    x: Optional[float] = doc(
        "camera ground frame x on the robot [m]; unset: the dataset's rig.toml, else 0", None
    )
    y: Optional[float] = doc(
        "camera ground frame y on the robot [m]; unset: rig.toml, else 0", None
    )
    yaw: Optional[float] = doc("camera heading on the robot [rad]; unset: rig.toml, else 0", None)


@dataclass
class MapConfig:
    cell_size_m: float = doc("cell side [m] (the paper: 4 cm)", 0.04)
    clamp_min_nats: float = doc("lowest log-odds a cell holds [nats] (OctoMap-style clamp)", -2.0)
    clamp_max_nats: float = doc("highest log-odds a cell holds [nats]", 3.5)
    occupied_threshold: float = doc("probability at or above which a cell is occupied", 0.65)
    free_threshold: float = doc("probability at or below which a cell is free", 0.196)
    local_size_m: float = doc("side of the robot-centred local map [m] (the paper: 3.84 m)", 3.84)
    max_cells: int = doc(
        "most cells the global map may span (default 2^25: 231 m square at 4 cm); a pose farther out is skipped and counted (docs/limits.md)",
        1 << 25,
    )


@dataclass
class EvidenceConfig:
    hit_nats: float = doc("log-odds added to a cell seen occupied [nats], > 0", 0.85)
    miss_nats: float = doc("log-odds added to a cell seen free [nats], < 0", -0.4)


@dataclass
class SensorsConfig:
    visual: EvidenceConfig = field(default_factory=EvidenceConfig, metadata={"doc": "camera scans"})
    laser: EvidenceConfig = field(default_factory=EvidenceConfig, metadata={"doc": "laser scans"})
    sonar: EvidenceConfig = field(
        default_factory=lambda: EvidenceConfig(hit_nats=0.4, miss_nats=-0.2),
        metadata={"doc": "sonar readings"},
    )
    too_close: str = doc("too_close columns: mark_near_edge | ignore", "mark_near_edge")
    boundary_margin_rows: float = doc(
        "floor left unobserved before a visual boundary, in pixel rows of its footprint (0: the paper's rule)",
        0.5,
    )


@dataclass
class OutputsConfig:
    local_snapshot_period_s: float = doc(
        "seconds between local map snapshots (PNG); 0 disables", 5.0
    )
    overlay: str = doc("frames with boundary points: gif | mp4 | none", "gif")
    overlay_max_frames: int = doc(
        "frames in the overlay animation (evenly spread over the run)", 120
    )
    overlay_max_mb: int = doc(
        "most memory the kept overlay frames may take [MB]; fewer frames are kept past it", 256
    )
    bag: bool = doc("write scans (LaserScan) and the map (OccupancyGrid) to a ROS 2 bag", True)
    bag_storage: str = doc("ROS 2 bag storage: mcap | sqlite3", "mcap")
    laser_angle_increment_rad: float = doc("angular bin of the LaserScan conversion [rad]", 0.01)


@dataclass
class LimitsConfig:
    max_image_pixels: int = doc(
        "largest image decoded (width x height); larger ones, decompression bombs among them, are refused unread (docs/limits.md)",
        1 << 26,
    )


@dataclass
class NodeConfig:
    transport: str = doc(
        "middleware of `floorscan node`: ros1 (rospy, a ROS 1 master) | zenoh (ROS 2's rmw_zenoh)",
        "ros1",
    )
    image_topic: str = doc(
        "camera topic (sensor_msgs/Image mono8/rgb8/bgr8/mono16 or CompressedImage)",
        "/camera/image_raw",
    )
    compressed: bool = doc("the image topic carries sensor_msgs/CompressedImage", False)
    odom_topic: str = doc(
        'odometry topic (nav_msgs/Odometry); "" for none (local map only)', "/odom"
    )
    odom_source: str = doc(
        "where poses come from: odometry (nav_msgs/Odometry on odom_topic) | tf (odom_frame -> base_frame on tf_topic)",
        "odometry",
    )
    tf_topic: str = doc("transform topic read when odom_source = tf (tf2_msgs/TFMessage)", "/tf")
    odom_frame: str = doc("parent frame of the robot's pose when odom_source = tf", "odom")
    scan_topic: str = doc("LaserScan output topic (REP 117 ranges)", "/scan")
    map_topic: str = doc("global OccupancyGrid output topic", "/map")
    local_map_topic: str = doc("local (robot-centred) OccupancyGrid output topic", "/local_map")
    overlay_topic: str = doc(
        'camera frames with the boundary points drawn (sensor_msgs/Image rgb8); "" for none', ""
    )
    tf_static_topic: str = doc("static transform topic (base_frame -> scan_frame)", "/tf_static")
    base_frame: str = doc("robot frame (REP 105 base_link)", "base_link")
    scan_frame: str = doc("frame of the scans: the camera ground frame", "camera_ground")
    map_frame: str = doc("frame of both maps: the odometry frame they are built in", "odom")
    map_period_s: float = doc("seconds between map publications, > 0", 1.0)
    odom_timeout_s: float = doc(
        "a frame newer than the last odometry by more than this [s] is skipped and counted (odometry stopped)",
        0.5,
    )
    node_name: str = doc("node name on the ROS graph", "floorscan")
    domain_id: int = doc("ROS 2 domain id (zenoh transport), 0..=232", 0)
    zenoh_connect: str = doc(
        'zenoh endpoint to connect to (zenoh transport), "" for none', "tcp/localhost:7447"
    )
    zenoh_listen: str = doc('zenoh endpoint to listen on (zenoh transport), "" for none', "")
    zenoh_mode: str = doc("zenoh session mode: peer | client", "peer")
    foxglove_port: int = doc(
        "port of the Foxglove WebSocket live view on 127.0.0.1 (needs foxglove-sdk); 0: off", 0
    )


@dataclass
class Config:
    ranger: RangerConfig = field(default_factory=RangerConfig)
    appearance: AppearanceConfig = field(default_factory=AppearanceConfig)
    calibration: CalibrationConfig = field(default_factory=CalibrationConfig)
    rig: RigConfig = field(default_factory=RigConfig)
    map: MapConfig = field(default_factory=MapConfig)
    sensors: SensorsConfig = field(default_factory=SensorsConfig)
    outputs: OutputsConfig = field(default_factory=OutputsConfig)
    limits: LimitsConfig = field(default_factory=LimitsConfig)
    node: NodeConfig = field(default_factory=NodeConfig)

    # --- reading ------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, d: Dict[str, Any], *, source: str = "config") -> Config:
        return _build(cls, d, source, "")

    @classmethod
    def load(cls, path: PathLike) -> Config:
        return cls.from_dict(load_toml(Path(path)), source=str(path))

    @classmethod
    def from_toml(cls, text: str, *, source: str = "<config>") -> Config:
        return cls.from_dict(loads_toml(text, source=source), source=source)

    # --- writing ------------------------------------------------------------------------
    def to_dict(self) -> Dict[str, Any]:
        return _drop_none(dataclasses.asdict(self))

    def to_toml(self, *, with_docs: bool = True) -> str:
        comments = _docs(type(self), "") if with_docs else {}
        text = dumps_toml(self.to_dict(), comments)
        if with_docs:
            # Unset optional keys appear commented out, so users see they exist.
            lines = []
            for line in text.splitlines():
                lines.append(line)
                if line.startswith("["):
                    section = line.strip("[]")
                    for key, note in _unset_keys(self, section):
                        lines.append(f"# {key} = (unset)  # {note}")
            text = "\n".join(lines) + "\n"
        return "# floorscan configuration (floorscan config --default)\n" + text

    def save(self, path: PathLike) -> Path:
        return write_atomic(path, self.to_toml())

    def with_overrides(self, overrides: Dict[str, Any]) -> Config:
        """A copy with dotted keys replaced (``{"ranger.threshold": 9.0}``), type-checked."""
        d = dataclasses.asdict(self)
        for key, value in overrides.items():
            if value is None:
                continue
            node = d
            parts = key.split(".")
            for p in parts[:-1]:
                if p not in node or not isinstance(node[p], dict):
                    raise ConfigError(f"unknown key `{key}`")
                node = node[p]
            if parts[-1] not in node:
                raise ConfigError(f"unknown key `{key}`")
            node[parts[-1]] = value
        return Config.from_dict(_drop_none(d), source="command line")


def _drop_none(d):
    if isinstance(d, dict):
        return {k: _drop_none(v) for k, v in d.items() if v is not None}
    return d


def _docs(cls, prefix: str) -> Dict[str, str]:
    out = {}
    for f in fields(cls):
        if dataclasses.is_dataclass(f.type) or (
            isinstance(f.type, str) and f.type.endswith("Config")
        ):
            continue
        if "doc" in f.metadata:
            out[f"{prefix}{f.name}"] = f.metadata["doc"]
    hints = get_type_hints(cls)
    for f in fields(cls):
        t = hints[f.name]
        if dataclasses.is_dataclass(t):
            out.update(_docs(t, f"{prefix}{f.name}."))
    return out


def _unset_keys(cfg: Config, section: str):
    node: Any = cfg
    for p in section.split("."):
        node = getattr(node, p, None)
        if node is None:
            return []
    if not dataclasses.is_dataclass(node):
        return []
    return [
        (f.name, f.metadata.get("doc", "")) for f in fields(node) if getattr(node, f.name) is None
    ]


def _check_value(value: Any, typ: Any, key: str, source: str) -> Any:
    optional = get_origin(typ) is Union and type(None) in get_args(typ)
    if optional:
        typ = [a for a in get_args(typ) if a is not type(None)][0]
    if typ is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{source}: `{key}` must be true or false, got {value!r}")
        return value
    if typ is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{source}: `{key}` must be an integer, got {value!r}")
        return value
    if typ is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"{source}: `{key}` must be a number, got {value!r}")
        if math.isnan(value) or (math.isinf(value) and not optional):
            raise ConfigError(f"{source}: `{key}` must be finite, got {value!r}")
        return float(value)
    if typ is str:
        if not isinstance(value, str):
            raise ConfigError(f"{source}: `{key}` must be a string, got {value!r}")
        return value
    raise ConfigError(f"{source}: `{key}` has an unsupported type")  # pragma: no cover


def _build(cls, d: Any, source: str, prefix: str):
    if not isinstance(d, dict):
        raise ConfigError(f"{source}: `{prefix.rstrip('.') or 'config'}` must be a table")
    hints = get_type_hints(cls)
    names = {f.name for f in fields(cls)}
    for k in d:
        if k not in names:
            raise ConfigError(
                f"{source}: unknown key `{prefix}{k}` (known: {', '.join(sorted(names))})"
            )
    kwargs = {}
    for f in fields(cls):
        if f.name not in d:
            continue
        t = hints[f.name]
        key = f"{prefix}{f.name}"
        if dataclasses.is_dataclass(t):
            kwargs[f.name] = _build(t, d[f.name], source, key + ".")
        else:
            kwargs[f.name] = _check_value(d[f.name], t, key, source)
    return cls(**kwargs)
