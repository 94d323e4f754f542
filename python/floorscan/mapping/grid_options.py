"""Options of the map builder: the sensor evidence model, and the grid and inserter options in
the core's serde form (validated again, field by field, by the Rust core)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Dict, Sequence, Tuple, Union

import numpy as np

from ..errors import ArgumentTypeError, LengthMismatchError, OptionError
from ..options import defaults, plain

GRID_KEYS = frozenset(defaults("grid"))
"""Fields of the core's ``GridOptions`` (crates/floorscan-core/src/mapping/grid_options.rs)."""

INSERTER_KEYS = frozenset(defaults("inserter"))
"""Fields of the core's ``InserterOptions`` (crates/floorscan-core/src/mapping/inserter.rs)."""


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

    def to_native(self) -> Dict[str, float]:
        """The core's serde form (the ``[sensors.*]`` tables of the config file)."""
        return {"hit_nats": self.hit_nats, "miss_nats": self.miss_nats}


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


def _pair(name: str, value: Any) -> Any:
    """A point: ``(x, y)`` [m] as the core's ``{"x": .., "y": ..}``; a dict passes as it is."""
    if isinstance(value, dict):
        return value
    a = np.asarray(value, dtype=object).ravel()
    if a.size != 2:
        raise OptionError(f"invalid option `{name}`: must be a pair (x, y) [m], got {value!r}")
    return {"x": a[0], "y": a[1]}


def _bounds(value: Any) -> Any:
    if value is None or isinstance(value, dict):
        return value
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise OptionError(
            f"invalid option `bounds_m`: give ((x_min, y_min), (x_max, y_max)) [m], got {value!r}"
        ) from None
    return {"min": _pair("bounds_m", lo), "max": _pair("bounds_m", hi)}


def _evidence(name: str, value: Any) -> Any:
    if isinstance(value, Evidence):
        return value.to_native()
    if isinstance(value, dict):
        return value
    try:
        hit, miss = value
    except (TypeError, ValueError):
        raise OptionError(
            f"invalid option `{name}`: give an Evidence or (hit_nats, miss_nats), got {value!r}"
        ) from None
    return {"hit_nats": hit, "miss_nats": miss}


def split_options(options: Dict[str, Any]) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """Keyword options of a map as the core's ``GridOptions`` and ``InserterOptions`` dicts
    (serde form; omitted fields take the Rust defaults, unknown ones are reported by the core).
    Pairs are accepted for points (``origin_m=(x, y)``), bounds (``((x0, y0), (x1, y1))``) and
    evidence (``visual=(hit_nats, miss_nats)`` or an :class:`Evidence`)."""
    grid: Dict[str, Any] = {}
    inserter: Dict[str, Any] = {}
    for key, value in options.items():
        if key in INSERTER_KEYS:
            if key in ("visual", "laser", "sonar"):
                value = _evidence(key, value)
            inserter[key] = value
        else:
            if key == "origin_m":
                value = _pair(key, value)
            elif key == "bounds_m":
                value = _bounds(value)
            grid[key] = value
    return plain(grid), plain(inserter)


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
