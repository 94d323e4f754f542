"""The configuration file's tables that are Rust options types (``[ranger]``, ``[appearance]``,
``[grid]``, ``[local_map]``, ``[sensors]``, ``[slam]``, ``[parallax]``, ``[drive]``): each is the
serde form of its type, completed with the Rust defaults and checked by the Rust type
(:class:`OptionsTable`), plus the pipeline's own keys where a table has some
(:class:`RangerExtras`, :class:`AppearanceExtras`). :class:`~floorscan.pipeline.config.Config`
holds them.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field, fields
from typing import Any, Dict, Optional

from ..options import check, defaults


def doc(text: str, default: Any = dataclasses.MISSING, **kw):
    """A config dataclass field with its documentation (``floorscan config --default``)."""
    return field(default=default, metadata={"doc": text}, **kw)


@dataclass
class RangerExtras:
    """The pipeline's own keys of ``[ranger]`` (beside the Rust ``RangerOptions``)."""

    kind: str = doc(
        "range sensor: edge (the paper's box filter; the default: no other kind has fewer wrong columns on every real set with truth, `floorscan eval --real`, EVALUATION.md) | appearance (floor colour and texture model) | fused (appearance boundaries placed by nearby edges; fewer wrong columns on the simulator's tiles, more on real floors)",
        "edge",
    )
    auto_threshold: bool = doc(
        "set `threshold` (the least threshold) once from the first frame: auto_threshold_k x the carpet's texture noise near the robot (false: as configured; `noise_multiple` and `contrast` adapt every frame either way)",
        False,
    )
    auto_threshold_k: float = doc("multiple of the texture noise for the automatic threshold", 5.0)


_FUSION = defaults("fusion")
"""The fused ranger's defaults, from the core's ``FusionOptions``."""


@dataclass
class AppearanceExtras:
    """The pipeline's own keys of ``[appearance]`` (beside the Rust ``AppearanceOptions``)."""

    snap_rows: float = doc(
        "fused ranger: largest distance [rows] at which an edge replaces the appearance boundary",
        _FUSION["snap_rows"],
    )
    snap_fraction: float = doc(
        "fused ranger: the same distance as a share of the image height, in [0, 1]; the larger of the two applies",
        _FUSION["snap_fraction"],
    )
    texture_share: float = doc(
        "fused ranger: a frame where more than this share of the edge boundaries lie below appearance boundaries breaks the texture assumption, and its columns the appearance ranger saw as floor stay floor; in [0, 1], 1: never",
        _FUSION["texture_share"],
    )


SHARED_WITH_RANGER = ("columns", "start", "max_range_m")
"""Fields of ``AppearanceOptions`` that ``[appearance]`` takes from ``[ranger]``."""


class OptionsView(dict):
    """A dict of options with attribute access (``cfg.sensors.visual.hit_nats``)."""

    def __getattr__(self, name: str) -> Any:
        try:
            value = self[name]
        except KeyError:
            raise AttributeError(name) from None
        return OptionsView(value) if isinstance(value, dict) else value


class OptionsTable:
    """One table of the config file that is a Rust options type: its serde form, completed
    with the Rust defaults and validated by the Rust type; plus the pipeline's own keys
    (``extras``, a dataclass) where the table has some. Read-only; attribute access."""

    def __init__(self, kind: str, values: Dict[str, Any], extras: Any = None) -> None:
        self.__dict__.update(_kind=kind, _values=dict(values), _extras=extras)

    @property
    def options_kind(self) -> str:
        """The Rust options type (a key of :data:`floorscan.options.KINDS`)."""
        return self.__dict__["_kind"]

    @property
    def extras(self) -> Any:
        """The pipeline's own keys of the table (a dataclass), or None."""
        return self.__dict__["_extras"]

    def __getattr__(self, name: str) -> Any:
        values, extras = self.__dict__["_values"], self.__dict__["_extras"]
        if name in values:
            v = values[name]
            return OptionsView(v) if isinstance(v, dict) else v
        if extras is not None and name in {f.name for f in fields(extras)}:
            return getattr(extras, name)
        raise AttributeError(name)

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("config tables are read-only: use Config.with_overrides")

    def __eq__(self, other: object) -> bool:
        return isinstance(other, OptionsTable) and self.__dict__ == other.__dict__

    def __repr__(self) -> str:
        return f"OptionsTable({self.options_kind!r}, {self.to_dict()!r})"

    def options(self) -> Dict[str, Any]:
        """The Rust options of the table (serde form, every field)."""
        return dict(self.__dict__["_values"])

    def to_dict(self) -> Dict[str, Any]:
        extras = self.__dict__["_extras"]
        return {**self.options(), **(dataclasses.asdict(extras) if extras is not None else {})}


def ranger_table(values: Dict[str, Any], extras: Optional[RangerExtras] = None) -> OptionsTable:
    return OptionsTable("ranger", check("ranger", values), extras or RangerExtras())


def appearance_table(
    values: Dict[str, Any], ranger: OptionsTable, extras: Optional[AppearanceExtras] = None
) -> OptionsTable:
    shared = {k: ranger.options()[k] for k in SHARED_WITH_RANGER}
    full = check("appearance", {**values, **shared})
    own = {k: v for k, v in full.items() if k not in SHARED_WITH_RANGER}
    return OptionsTable("appearance", own, extras or AppearanceExtras())


def local_map_table(values: Dict[str, Any], grid: OptionsTable) -> OptionsTable:
    full = check("local_map", {**values, "grid": grid.options()})
    return OptionsTable("local_map", {k: v for k, v in full.items() if k != "grid"})


def default_tables() -> Dict[str, OptionsTable]:
    ranger = ranger_table({})
    grid = OptionsTable("grid", check("grid", {}))
    return {
        "ranger": ranger,
        "appearance": appearance_table({}, ranger),
        "grid": grid,
        "local_map": local_map_table({}, grid),
        "sensors": OptionsTable("inserter", check("inserter", {})),
        "slam": OptionsTable("slam", check("slam", {})),
        "parallax": OptionsTable("parallax", check("parallax", {})),
        "drive": OptionsTable("drive", check("drive", {})),
    }


RUST_TABLES = {
    "ranger": ("ranger", RangerExtras),
    "appearance": ("appearance", AppearanceExtras),
    "grid": ("grid", None),
    "local_map": ("local_map", None),
    "sensors": ("inserter", None),
    "slam": ("slam", None),
    "parallax": ("parallax", None),
    "drive": ("drive", None),
}
"""Config table -> (its Rust options type in :mod:`floorscan.options`, its pipeline keys)."""
