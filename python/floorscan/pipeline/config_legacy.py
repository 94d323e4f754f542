"""Spellings of configuration files written before the tables became the Rust options' serde
form, read into today's keys: ``[map]`` (now ``[grid]`` and ``[local_map]``),
``ranger.half_width``, ``ranger.refine``, ``ranger.bottom_margin`` and the appearance keys
without their units. ``floorscan config --check`` prints such a file in today's spelling.
"""

from __future__ import annotations

from typing import Any, Callable, Dict, Tuple

from ..errors import ConfigError


def _renamed(new: str, convert: Callable[[Any], Any] = lambda v: v) -> Tuple[str, Callable]:
    return new, convert


LEGACY_KEYS: Dict[str, Tuple[str, Callable[[Any], Any]]] = {
    "ranger.half_width": _renamed("ranger.half_width_px"),
    "ranger.refine": _renamed(
        "ranger.refinement",
        lambda v: {"subpixel": "sub_pixel", "none": "first_crossing"}.get(v, v),
    ),
    "ranger.bottom_margin": _renamed("ranger.start", lambda v: {"bottom_margin": v}),
    "appearance.intensity_reach": _renamed("appearance.intensity_reach_bins"),
    "appearance.patch_half_width": _renamed("appearance.patch_half_width_px"),
    "appearance.min_run": _renamed("appearance.min_run_px"),
    "appearance.features": _renamed(
        "appearance.features", lambda v: {"colour_texture": "colour_and_texture"}.get(v, v)
    ),
    "map.local_size_m": _renamed("local_map.size_m"),
    **{
        f"map.{k}": _renamed(f"grid.{k}")
        for k in (
            "cell_size_m",
            "origin_m",
            "bounds_m",
            "clamp_min_nats",
            "clamp_max_nats",
            "occupied_threshold",
            "free_threshold",
            "max_cells",
        )
    },
}
"""Spellings of config files written before the tables became the Rust serde form, read
into today's keys (old key -> (new key, value conversion)). Kept so that existing files keep
working; ``floorscan config --check`` prints the file in today's spelling."""


def modernise(d: Dict[str, Any], source: str) -> Dict[str, Any]:
    out = {k: (dict(v) if isinstance(v, dict) else v) for k, v in d.items()}
    for table in ("ranger", "appearance", "map"):
        old = out.get(table)
        if not isinstance(old, dict):
            continue
        for key in list(old):
            rule = LEGACY_KEYS.get(f"{table}.{key}")
            if rule is None:
                continue
            new, convert = rule
            new_table, new_key = new.split(".")
            value = convert(old.pop(key))
            out.setdefault(new_table, {})
            if isinstance(out[new_table], dict):
                out[new_table][new_key] = value
        if table == "map":
            for key in old:
                raise ConfigError(f"{source}: unknown key `map.{key}` ([map] is now [grid])")
            del out["map"]
    return out
