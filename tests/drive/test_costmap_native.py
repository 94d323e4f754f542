"""The navigation function's coarse grid in the Rust core against the numpy block reductions
it replaced: the same blocked cells and the same weights, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan._native.drive import coarse_grid
from floorscan.drive.costmap import INSCRIBED
from floorscan.errors import FloorscanError


def _numpy_coarse(cost, f, unknown_cost, known):
    h, w = cost.shape[0] // f, cost.shape[1] // f
    blocks = cost[: h * f, : w * f].reshape(h, f, w, f).astype(np.float64)
    blocked = blocks.min(axis=(1, 3)) >= INSCRIBED
    weight = 1.0 + np.minimum(blocks.mean(axis=(1, 3)), INSCRIBED) / 64.0
    if known is not None:
        k = known[: h * f, : w * f].reshape(h, f, w, f).mean(axis=(1, 3))
        weight = weight + unknown_cost * (1.0 - k)
    return blocked, weight


@pytest.mark.parametrize("f", [1, 2, 3, 5])
def test_coarse_grid_equals_the_numpy_block_reductions(f):
    rng = np.random.default_rng(f)
    cost = rng.choice([0, 3, 40, 120, 252, 253, 254], size=(161, 157)).astype(np.uint8)
    known = rng.uniform(size=cost.shape) < 0.6
    for k in (None, known):
        blocked, weight = coarse_grid(cost, f, INSCRIBED, 2.0, k)
        b_ref, w_ref = _numpy_coarse(cost, f, 2.0, k)
        assert np.array_equal(blocked, b_ref)
        assert np.array_equal(weight, w_ref)


def test_bad_arguments_are_errors():
    cost = np.zeros((10, 10), np.uint8)
    with pytest.raises(FloorscanError):
        coarse_grid(cost, 0, INSCRIBED, 2.0)
    with pytest.raises(FloorscanError):
        coarse_grid(cost, 2, INSCRIBED, 2.0, np.zeros((9, 10), bool))
