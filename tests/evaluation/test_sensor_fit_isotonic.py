"""Isotonic calibration against its closed form: the least-squares non-decreasing fit is
f(i) = max over j <= i of min over k >= i of the weighted mean of y[j..k]."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan.drive.avoidance_map import AvoidanceMap, AvoidanceMapOptions
from floorscan.errors import OptionError
from floorscan.evaluation.sensor_fit import isotonic


def _minmax(y, w):
    n = len(y)
    out = np.empty(n)
    for i in range(n):
        best = -np.inf
        for j in range(i + 1):
            worst = np.inf
            for k in range(i, n):
                worst = min(worst, np.average(y[j : k + 1], weights=w[j : k + 1]))
            best = max(best, worst)
        out[i] = best
    return out


@pytest.mark.parametrize("seed", range(5))
def test_pool_adjacent_violators_equals_the_min_max_formula(seed):
    rng = np.random.default_rng(seed)
    x = rng.permutation(20).astype(float)
    y = rng.uniform(0, 1, 20)
    w = rng.uniform(0.5, 3, 20)
    fit = isotonic(x, y, w)
    order = np.argsort(x)
    assert np.allclose(fit[order], _minmax(y[order], w[order]))


def test_knots_map_log_odds_to_probabilities_and_are_validated():
    opts = AvoidanceMapOptions(probability_knots=((-2.0, 0.02), (0.0, 0.3), (2.0, 0.9)))
    m = AvoidanceMap(opts)
    log_odds = m.log_odds
    log_odds[0, :4] = [-3.0, -1.0, 1.0, 3.0]
    m.log_odds = log_odds
    p = m.probabilities()[0, :4]
    assert np.allclose(p, [0.02, 0.16, 0.6, 0.9])
    with pytest.raises(OptionError):
        AvoidanceMapOptions(probability_knots=((0.0, 0.5), (1.0, 0.4)))  # decreasing
    with pytest.raises(OptionError):
        AvoidanceMapOptions(probability_knots=((0.0, 0.5),))
