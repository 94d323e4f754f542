"""Log-odds as the cells store them (floorscan-core's ``log_odds``): int16 thousandths of a
nat, the conversions to and from probability, and the occupancy classes. Every number here
comes from the Rust core through the binding.
"""

from __future__ import annotations

import enum

import numpy as np

from .._native import mapping as _native

UNITS_PER_NAT: float = _native.UNITS_PER_NAT
"""Stored log-odds units per nat (floorscan-core's ``log_odds::UNITS_PER_NAT``: cells hold
int16 thousandths of a nat)."""

Occupancy = enum.IntEnum(
    "Occupancy", {name.upper(): code for name, code in _native.occupancy_classes()}
)
Occupancy.__doc__ = """What a cell's evidence says by the map's thresholds (floorscan-core's
``Occupancy``, built from it): the codes of :meth:`GridViews.occupancy_classes`.

>>> [(o.name, int(o)) for o in Occupancy]
[('FREE', 0), ('UNKNOWN', 1), ('OCCUPIED', 2)]
"""

OCCUPANCY_CLASSES = tuple(o.name.lower() for o in Occupancy)
"""Names of the codes returned by :meth:`occupancy_classes` (0, 1, 2)."""


def probabilities_from_units(units: np.ndarray) -> np.ndarray:
    """Probability of occupancy (float64, same shape) of stored log-odds units [1/1000 nat]:
    floorscan-core's ``probability_from_log_odds``.

    >>> probabilities_from_units(np.array([0, 2000])).round(4).tolist()
    [0.5, 0.8808]
    """
    return _native.probabilities_from_units(np.asarray(units, dtype=np.int32))


def units_from_probabilities(p: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """Stored log-odds units (int16, rounded, clamped to ``[lo, hi]``) of probabilities:
    floorscan-core's ``log_odds_from_probability``; NaN gives 0 (unknown).

    >>> units_from_probabilities(np.array([0.5, 0.8808, 1.0]), -2000, 3500).tolist()
    [0, 2000, 3500]
    """
    return _native.units_from_probabilities(np.asarray(p, dtype=np.float64), int(lo), int(hi))
