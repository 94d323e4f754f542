"""Log-odds units, conversions and occupancy classes come from the Rust core: checked against
the analytic formulas and against what a grid does."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import Occupancy, OccupancyGrid
from floorscan.mapping.log_odds import (
    UNITS_PER_NAT,
    probabilities_from_units,
    units_from_probabilities,
)


def test_probabilities_are_the_logistic_of_thousandths_of_a_nat():
    units = np.array([[-16000, -2000, 0], [1, 850, 16000]], np.int16)
    expected = 1.0 / (1.0 + np.exp(-units.astype(np.float64) / 1000.0))
    got = probabilities_from_units(units)
    assert got.shape == units.shape and UNITS_PER_NAT == 1000.0
    np.testing.assert_allclose(got, expected, rtol=1e-12)


def test_units_round_trip_and_clamp():
    u = np.arange(-2000, 3501, 37)
    back = units_from_probabilities(probabilities_from_units(u), -2000, 3500)
    np.testing.assert_array_equal(back, u)
    edge = units_from_probabilities(np.array([0.0, 1.0, np.nan, 0.5]), -2000, 3500)
    assert edge.tolist() == [-2000, 3500, 0, 0]
    p = np.array([0.1, 0.7, 0.97])
    np.testing.assert_array_equal(
        units_from_probabilities(p, -16000, 16000), np.round(1000 * np.log(p / (1 - p)))
    )


@pytest.mark.parametrize("cls", list(Occupancy))
def test_occupancy_codes_are_the_grids_classes(cls):
    grid = OccupancyGrid(cell_size_m=0.1)
    # Write one cell at the lower clamp (free), 0 (unknown) or the upper clamp (occupied).
    lo, hi = (
        round(grid.options["grid"][k] * UNITS_PER_NAT) for k in ("clamp_min_nats", "clamp_max_nats")
    )
    value = {Occupancy.FREE: lo, Occupancy.UNKNOWN: 0, Occupancy.OCCUPIED: hi}[cls]
    grid.write_raw(np.array([[value]], np.int16), x_cell=0, y_cell=0)
    assert int(grid.occupancy_classes()[0, 0]) == cls
