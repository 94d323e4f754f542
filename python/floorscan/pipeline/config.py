"""The one configuration file: every parameter of ranger, calibration, rig, map, sensors and
outputs, with documented defaults. ``floorscan config --default`` prints it; command-line flags
override it; unknown, ill-typed or out-of-range keys are errors that name the key.

The tables ``[ranger]``, ``[appearance]``, ``[grid]``, ``[local_map]``, ``[sensors]`` and
``[slam]``, ``[parallax]`` are exactly the serde form of the Rust options types (``RangerOptions``,
``AppearanceOptions``, ``GridOptions``, ``LocalMapOptions``, ``InserterOptions``,
``SlamOptions``, ``ParallaxOptions``): their defaults, docs and checks are
the Rust ones, read through :mod:`floorscan.options`. ``[ranger]`` also holds the pipeline's
own keys (``kind``, ``auto_threshold``...) and ``[appearance]`` takes ``columns``, ``start`` and
``max_range_m`` from ``[ranger]``; ``[local_map]`` takes its grid from ``[grid]``. The other
tables are the Python components' options (dataclasses below, defaults beside their fields).

The Rust tables and their pipeline keys live in :mod:`floorscan.pipeline.config_tables`;
older spellings of existing config files are still read
(:data:`~floorscan.pipeline.config_legacy.LEGACY_KEYS`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import re
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Dict, Optional, Tuple, Union, get_args, get_origin, get_type_hints

from .._atomic import PathLike, write_atomic
from ..calibration.options import CalibrationOptions
from ..errors import ConfigError, OptionError
from ..formats.toml_file import dumps_toml, load_toml, loads_toml
from ..options import check, field_docs
from .config_legacy import LEGACY_KEYS, modernise
from .config_tables import (
    RUST_TABLES,
    SHARED_WITH_RANGER,
    OptionsTable,
    appearance_table,
    default_tables,
    doc,
    local_map_table,
    ranger_table,
)

_CAL = CalibrationOptions()


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
    tf_topic: str = doc(
        "transform topic (tf2_msgs/TFMessage): read when odom_source = tf, map_frame -> odom_frame published on it",
        "/tf",
    )
    odom_frame: str = doc(
        "the odometry frame: parent of the robot's pose when odom_source = tf, child of map_frame",
        "odom",
    )
    scan_topic: str = doc("LaserScan output topic (REP 117 ranges)", "/scan")
    map_topic: str = doc("global OccupancyGrid output topic", "/map")
    local_map_topic: str = doc("local (robot-centred) OccupancyGrid output topic", "/local_map")
    overlay_topic: str = doc(
        'camera frames with the boundary points drawn (sensor_msgs/Image rgb8); "" for none', ""
    )
    tf_static_topic: str = doc("static transform topic (base_frame -> scan_frame)", "/tf_static")
    base_frame: str = doc("robot frame (REP 105 base_link)", "base_link")
    scan_frame: str = doc("frame of the scans: the camera ground frame", "camera_ground")
    map_frame: str = doc(
        "frame of both maps, built from the corrected poses; the node publishes map_frame -> odom_frame on tf_topic each frame (the scan matcher's correction, identity with [slam] off), as slam_toolbox does; equal to odom_frame: the maps in the odometry frame and no transform",
        "map",
    )
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
    ranger: OptionsTable = field(default_factory=lambda: default_tables()["ranger"])
    appearance: OptionsTable = field(default_factory=lambda: default_tables()["appearance"])
    calibration: CalibrationConfig = field(default_factory=CalibrationConfig)
    rig: RigConfig = field(default_factory=RigConfig)
    grid: OptionsTable = field(default_factory=lambda: default_tables()["grid"])
    local_map: OptionsTable = field(default_factory=lambda: default_tables()["local_map"])
    sensors: OptionsTable = field(default_factory=lambda: default_tables()["sensors"])
    slam: OptionsTable = field(default_factory=lambda: default_tables()["slam"])
    parallax: OptionsTable = field(default_factory=lambda: default_tables()["parallax"])
    drive: OptionsTable = field(default_factory=lambda: default_tables()["drive"])
    outputs: OutputsConfig = field(default_factory=OutputsConfig)
    limits: LimitsConfig = field(default_factory=LimitsConfig)
    node: NodeConfig = field(default_factory=NodeConfig)

    # --- reading ------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, d: Dict[str, Any], *, source: str = "config") -> Config:
        if not isinstance(d, dict):
            raise ConfigError(f"{source}: `config` must be a table")
        d = modernise(d, source)
        names = {f.name for f in fields(cls)}
        for k in d:
            if k not in names:
                raise ConfigError(
                    f"{source}: unknown key `{k}` (known: {', '.join(sorted(names))})"
                )
        for k in RUST_TABLES:
            if k in d and not isinstance(d[k], dict):
                raise ConfigError(f"{source}: `{k}` must be a table")
        tables: Dict[str, Any] = {}

        def split(name: str) -> Tuple[Dict[str, Any], Any]:
            _, extras_cls = RUST_TABLES[name]
            raw = dict(d.get(name, {}))
            if extras_cls is None:
                return raw, None
            own = {f.name for f in fields(extras_cls)}
            extras = {k: raw.pop(k) for k in list(raw) if k in own}
            return raw, _build(extras_cls, extras, source, f"{name}.")

        with _named(source, "ranger"):
            values, extras = split("ranger")
            tables["ranger"] = ranger_table(values, extras)
        with _named(source, "appearance"):
            values, extras = split("appearance")
            for k in SHARED_WITH_RANGER:
                if k in values:
                    raise ConfigError(
                        f"{source}: `appearance.{k}` is set in [ranger] (`ranger.{k}`)"
                    )
            tables["appearance"] = appearance_table(values, tables["ranger"], extras)
        with _named(source, "grid"):
            tables["grid"] = OptionsTable("grid", check("grid", split("grid")[0]))
        with _named(source, "local_map"):
            values = split("local_map")[0]
            if "grid" in values:
                raise ConfigError(f"{source}: `local_map.grid` is the [grid] table")
            tables["local_map"] = local_map_table(values, tables["grid"])
        with _named(source, "sensors"):
            tables["sensors"] = OptionsTable("inserter", check("inserter", split("sensors")[0]))
        with _named(source, "slam"):
            tables["slam"] = OptionsTable("slam", check("slam", split("slam")[0]))
        with _named(source, "parallax"):
            tables["parallax"] = OptionsTable("parallax", check("parallax", split("parallax")[0]))
        with _named(source, "drive"):
            tables["drive"] = OptionsTable("drive", check("drive", split("drive")[0]))
        rest = {k: v for k, v in d.items() if k not in RUST_TABLES}
        return _build(cls, rest, source, "", **tables)

    @classmethod
    def load(cls, path: PathLike) -> Config:
        return cls.from_dict(load_toml(Path(path)), source=str(path))

    @classmethod
    def from_toml(cls, text: str, *, source: str = "<config>") -> Config:
        return cls.from_dict(loads_toml(text, source=source), source=source)

    # --- writing ------------------------------------------------------------------------
    def to_dict(self) -> Dict[str, Any]:
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            out[f.name] = v.to_dict() if isinstance(v, OptionsTable) else dataclasses.asdict(v)
        return _drop_none(out)

    def to_toml(self, *, with_docs: bool = True) -> str:
        comments = _docs(self) if with_docs else {}
        text = dumps_toml(self.to_dict(), comments)
        if with_docs:
            # Unset optional keys appear commented out, so users see they exist.
            lines = []
            for line in text.splitlines():
                lines.append(line)
                if line.startswith("["):
                    section = line.strip("[]")
                    for key, note in _unset_keys(self, section, comments):
                        lines.append(f"# {key} = (unset)  # {note}")
            text = "\n".join(lines) + "\n"
        return "# floorscan configuration (floorscan config --default)\n" + text

    def save(self, path: PathLike) -> Path:
        return write_atomic(path, self.to_toml())

    def with_overrides(self, overrides: Dict[str, Any]) -> Config:
        """A copy with dotted keys replaced (``{"ranger.threshold": 9.0}``), checked."""
        d = self.to_dict()
        for key, value in overrides.items():
            if value is None:
                continue
            rule = LEGACY_KEYS.get(key)
            if rule is not None:
                key, value = rule[0], rule[1](value)
            node = d
            parts = key.split(".")
            for p in parts[:-1]:
                if p not in node or not isinstance(node[p], dict):
                    raise ConfigError(f"unknown key `{key}`")
                node = node[p]
            if parts[-1] not in node and not _optional_key(self, parts):
                raise ConfigError(f"unknown key `{key}`")
            node[parts[-1]] = value
        return Config.from_dict(d, source="command line")


def default_value(key: str) -> Any:
    """The default of a dotted config key (``"grid.cell_size_m"``), for command-line help."""
    node: Any = Config().to_dict()
    for p in key.split("."):
        node = node[p]
    return node


@contextlib.contextmanager
def _named(source: str, table: str):
    """Re-raises a Rust options error as a ConfigError naming the file and the dotted key."""
    try:
        yield
    except ConfigError:
        raise
    except OptionError as e:
        msg = re.sub(r"^invalid option `", f"invalid option `{table}.", str(e))
        raise ConfigError(f"{source}: {msg}") from None


def _optional_key(cfg: Config, parts) -> bool:
    """True for an unset optional key (a None field, left out of ``to_dict``)."""
    node: Any = cfg
    for i, p in enumerate(parts[:-1]):
        node = getattr(node, p, None)
        if isinstance(node, OptionsTable):
            # the rest of the key walks the table's options (``slam.matcher.<key>``)
            options: Any = node.options()
            for q in parts[i + 1 : -1]:
                options = options.get(q) if isinstance(options, dict) else None
            return isinstance(options, dict) and parts[-1] in options
    return dataclasses.is_dataclass(node) and parts[-1] in {f.name for f in fields(node)}


def _drop_none(d):
    if isinstance(d, dict):
        return {k: _drop_none(v) for k, v in d.items() if v is not None}
    return d


def _docs(cfg: Config) -> Dict[str, str]:
    """Dotted key -> comment: the Rust field docs of the options tables, the ``doc`` metadata
    of the dataclass tables."""
    out: Dict[str, str] = {}
    for f in fields(cfg):
        table = getattr(cfg, f.name)
        if isinstance(table, OptionsTable):
            for key, text in field_docs(table.options_kind).items():
                if text:
                    out[f"{f.name}.{key}"] = text
            if table.extras is not None:
                out.update(_dataclass_docs(table.extras, f"{f.name}."))
        else:
            out.update(_dataclass_docs(table, f"{f.name}."))
    return out


def _dataclass_docs(obj, prefix: str) -> Dict[str, str]:
    out = {}
    for f in fields(obj):
        if "doc" in f.metadata:
            out[f"{prefix}{f.name}"] = f.metadata["doc"]
        if dataclasses.is_dataclass(getattr(obj, f.name)):
            out.update(_dataclass_docs(getattr(obj, f.name), f"{prefix}{f.name}."))
    return out


def _unset_keys(cfg: Config, section: str, docs: Dict[str, str]):
    node: Any = cfg
    for p in section.split("."):
        node = getattr(node, p, None)
        if node is None:
            return []
    if isinstance(node, OptionsTable):
        names = [k for k, v in node.options().items() if v is None]
    elif isinstance(node, dict):  # a nested struct of an options table ([slam.matcher])
        names = [k for k, v in node.items() if v is None]
    elif dataclasses.is_dataclass(node):
        names = [f.name for f in fields(node) if getattr(node, f.name) is None]
    else:
        return []
    return [(k, docs.get(f"{section}.{k}", "")) for k in names]


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


def _build(cls, d: Any, source: str, prefix: str, **given):
    if not isinstance(d, dict):
        raise ConfigError(f"{source}: `{prefix.rstrip('.') or 'config'}` must be a table")
    hints = get_type_hints(cls)
    names = {f.name for f in fields(cls)}
    for k in d:
        if k not in names:
            raise ConfigError(
                f"{source}: unknown key `{prefix}{k}` (known: {', '.join(sorted(names))})"
            )
    kwargs = dict(given)
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
