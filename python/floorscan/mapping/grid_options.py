"""Options of the map builder: the sensor evidence model, and the grid and inserter options in
the core's serde form (validated again, field by field, by the Rust core)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Dict, Optional, Sequence, Tuple, Union

import numpy as np

from ..errors import ArgumentTypeError, LengthMismatchError, OptionError

DEFAULT_MAX_CELLS = 1 << 25
"""Default ``max_cells`` of a map (33.5 M cells: 231 m square at 4 cm); see docs/limits.md."""

TOO_CLOSE_POLICIES = {
    "mark": "mark_near_edge",
    "mark_near_edge": "mark_near_edge",
    "ignore": "ignore",
}
"""Accepted ``too_close`` values: ``"mark"`` (or ``"mark_near_edge"``, the config file's name: a
hit at the near edge of view) or ``"ignore"``."""


@dataclass(frozen=True)
class Evidence:
    """How much one observation moves a cell, in nats of log-odds (the paper's evidence
    accumulator): ``hit_nats`` > 0 is added to a cell seen occupied, ``miss_nats`` < 0 to a
    cell seen free. Both within 16 nats in magnitude.

    Large steps suit a sensor that is rarely wrong (few observations decide a cell, the robot
    may drive faster); small steps suit a noisy one. :meth:`from_error_rates` derives them from
    a sensor's error rates.

    >>> e = Evidence.from_error_rates(false_alarm=0.1, miss_rate=0.1)
    >>> round(e.hit_nats, 4), round(e.miss_nats, 4)
    (2.1972, -2.1972)
    """

    hit_nats: float
    miss_nats: float

    @classmethod
    def from_error_rates(cls, *, false_alarm: float, miss_rate: float) -> Evidence:
        """Log-likelihood ratios of a detector that reports an obstacle where there is none
        with probability ``false_alarm`` and misses one with probability ``miss_rate`` (both
        in (0, 0.5)): ``hit = ln((1 - miss_rate) / false_alarm)``,
        ``miss = ln(miss_rate / (1 - false_alarm))``."""
        for name, v in (("false_alarm", false_alarm), ("miss_rate", miss_rate)):
            if not (0.0 < float(v) < 0.5):
                raise OptionError(f"invalid option `{name}`: must be in (0, 0.5), got {v}")
        return cls(math.log((1 - miss_rate) / false_alarm), math.log(miss_rate / (1 - false_alarm)))

    def to_native(self, name: str) -> Dict[str, float]:
        hit, miss = (
            _number(f"{name}.hit_nats", self.hit_nats),
            _number(f"{name}.miss_nats", self.miss_nats),
        )
        return {"hit_nats": hit, "miss_nats": miss}


EvidenceLike = Union[Evidence, Tuple[float, float], Sequence[float]]


def as_evidence(value: EvidenceLike, name: str) -> Evidence:
    if isinstance(value, Evidence):
        return value
    try:
        hit, miss = value
    except (TypeError, ValueError):
        raise OptionError(
            f"invalid option `{name}`: give an Evidence or (hit_nats, miss_nats), got {value!r}"
        ) from None
    return Evidence(float(hit), float(miss))


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool):
        raise OptionError(f"invalid option `{name}`: must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise OptionError(f"invalid option `{name}`: must be a number, got {value!r}") from None


def _count(name: str, value: Any, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
        raise OptionError(
            f"invalid option `{name}`: must be an integer in [{lo}, {hi}], got {value!r}"
        )
    return int(value)


def _pair(name: str, value: Any) -> Tuple[float, float]:
    a = np.asarray(value, dtype=object).ravel()
    if a.size != 2:
        raise OptionError(f"invalid option `{name}`: must be a pair (x, y) [m], got {value!r}")
    return _number(name, a[0]), _number(name, a[1])


def grid_options(
    *,
    cell_size_m: float,
    origin_m: Sequence[float],
    bounds_m: Optional[Sequence[Sequence[float]]],
    clamp_min_nats: float,
    clamp_max_nats: float,
    occupied_threshold: float,
    free_threshold: float,
    max_cells: int = DEFAULT_MAX_CELLS,
) -> Dict[str, Any]:
    """The core's ``GridOptions`` (see crates/floorscan-core/src/grid_options.rs)."""
    ox, oy = _pair("origin_m", origin_m)
    bounds = None
    if bounds_m is not None:
        try:
            lo, hi = bounds_m
        except (TypeError, ValueError):
            raise OptionError(
                "invalid option `bounds_m`: give ((x_min, y_min), (x_max, y_max)) [m], "
                f"got {bounds_m!r}"
            ) from None
        (x0, y0), (x1, y1) = _pair("bounds_m", lo), _pair("bounds_m", hi)
        bounds = {"min": {"x": x0, "y": y0}, "max": {"x": x1, "y": y1}}
    return {
        "cell_size_m": _number("cell_size_m", cell_size_m),
        "origin_m": {"x": ox, "y": oy},
        "bounds_m": bounds,
        "clamp_min_nats": _number("clamp_min_nats", clamp_min_nats),
        "clamp_max_nats": _number("clamp_max_nats", clamp_max_nats),
        "occupied_threshold": _number("occupied_threshold", occupied_threshold),
        "free_threshold": _number("free_threshold", free_threshold),
        "max_cells": _count("max_cells", max_cells, 1, 2**32),
    }


def inserter_options(
    *,
    visual: EvidenceLike,
    laser: EvidenceLike,
    sonar: EvidenceLike,
    too_close: str,
    boundary_margin_rows: float = 0.5,
) -> Dict[str, Any]:
    """The core's ``InserterOptions`` (see crates/floorscan-core/src/inserter.rs)."""
    if too_close not in TOO_CLOSE_POLICIES:
        raise OptionError(
            f"invalid option `too_close`: expected one of {sorted(TOO_CLOSE_POLICIES)}, "
            f"got {too_close!r}"
        )
    return {
        "visual": as_evidence(visual, "visual").to_native("visual"),
        "laser": as_evidence(laser, "laser").to_native("laser"),
        "sonar": as_evidence(sonar, "sonar").to_native("sonar"),
        "too_close": TOO_CLOSE_POLICIES[too_close],
        "boundary_margin_rows": _margin(boundary_margin_rows),
    }


def _margin(value: Any) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise OptionError(
            f"invalid option `boundary_margin_rows`: must be a number, got {value!r}"
        ) from None
    if not (np.isfinite(v) and v >= 0):
        raise OptionError(
            f"invalid option `boundary_margin_rows`: must be finite and >= 0, got {v}"
        )
    return v


Pose = Tuple[float, float, float]


def as_pose(value: Any, name: str) -> Pose:
    """``(x [m], y [m], yaw [rad])`` from a sequence of three numbers or an object with ``x``,
    ``y`` and ``yaw`` attributes. Finiteness is checked by the core (GeometryError)."""
    if all(hasattr(value, a) for a in ("x", "y", "yaw")):
        value = (value.x, value.y, value.yaw)
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"`{name}` must be (x, y, yaw), got {value!r}") from None
    if a.shape != (3,):
        raise ArgumentTypeError(f"`{name}` must be (x [m], y [m], yaw [rad]), got shape {a.shape}")
    return float(a[0]), float(a[1]), float(a[2])


def as_poses(value: Any, name: str) -> np.ndarray:
    """An (N, 3) contiguous float64 array of poses."""
    a = np.ascontiguousarray(value, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise LengthMismatchError(f"`{name}` must have shape (N, 3) (x, y, yaw), got {a.shape}")
    return a
