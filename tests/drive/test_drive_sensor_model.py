"""The inverse sensor model's fitting and the reliability diagram, against data with known
answers; the model's options."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import OptionError
from floorscan.drive import AvoidanceMap, AvoidanceMapOptions, VisualSensorModel
from floorscan.evaluation.sensor_fit import (
    _logistic_fit,
    reliability,
    reliability_of,
    wilson_interval,
)
from floorscan.sim import OccupancyRaster


def test_logistic_fit_recovers_known_parameters():
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 3, 200_000)
    p = 1 / (1 + np.exp(-(-2.0 + 0.8 * x)))
    y = (rng.uniform(size=x.size) < p).astype(float)
    a, b = _logistic_fit(x, y)
    assert a == pytest.approx(-2.0, abs=0.05)
    assert b == pytest.approx(0.8, abs=0.03)


def test_reliability_diagram_of_a_hand_made_map():
    opts = AvoidanceMapOptions(
        size_m=2.0,
        cell_size_m=0.1,
        probability_scale=1.0,
        probability_offset=0.0,
        probability_knots=None,
    )
    m = AvoidanceMap(opts, center=(1.0, 1.0))
    n = m.n
    cells = np.zeros((n, n), np.int8)  # truth: free except where set below
    # predicted 0.8 on 10 cells of which 8 are occupied; 0.15 on 20 cells of which 3 are
    log_odds = m.log_odds
    log_odds[0, :10] = np.log(0.8 / 0.2)
    cells[0, :8] = 100
    log_odds[1, :20] = np.log(0.15 / 0.85)
    m.log_odds = log_odds
    cells[1, :3] = 100
    raster = OccupancyRaster(cells=cells, origin=m.origin_m, resolution_m=0.1)
    rows = {r["decile"]: r for r in reliability(m, raster)}
    assert rows["0.8-0.9"]["cells"] == 10
    assert rows["0.8-0.9"]["observed"] == pytest.approx(0.8)
    assert rows["0.8-0.9"]["predicted"] == pytest.approx(0.8, abs=1e-6)
    assert rows["0.1-0.2"]["observed"] == pytest.approx(0.15)
    assert sum(r["cells"] for r in rows.values()) == 30  # cells without evidence left out
    # 8 of 10: the Wilson interval (textbook value 0.490-0.943) holds the frequency
    assert rows["0.8-0.9"]["observed_low"] == pytest.approx(0.490, abs=1e-3)
    assert rows["0.8-0.9"]["observed_high"] == pytest.approx(0.943, abs=1e-3)


def test_wilson_interval_covers_the_true_frequency_95_percent_of_the_time():
    # brute force: many binomial draws at a few true frequencies and sizes
    rng = np.random.default_rng(3)
    for q, n in ((0.05, 40), (0.5, 12), (0.8, 200)):
        k = rng.binomial(n, q, size=4000)
        cover = np.mean([lo <= q <= hi for lo, hi in (wilson_interval(int(x), n) for x in k)])
        assert 0.93 <= cover <= 0.99
    assert wilson_interval(0, 0) == (0.0, 1.0)


def test_pooled_reliability_is_the_reliability_of_the_pooled_cells():
    rng = np.random.default_rng(4)
    p = rng.uniform(size=5000)
    occ = rng.uniform(size=5000) < p  # calibrated by construction
    rows = reliability_of(p, occ)
    assert len(rows) == 10 and sum(r["cells"] for r in rows) == 5000
    for r in rows:
        assert r["observed_low"] <= r["observed"] <= r["observed_high"]
        assert abs(r["predicted"] - r["observed"]) < 0.06


def test_sigma_grows_with_footprint_and_error():
    m = VisualSensorModel()
    s = m.sigma_m(np.array([0.0, 0.03, np.nan]), np.array([0.0, 0.0, 0.04]), 0.0)
    assert s[0] == 0.0
    assert s[1] == pytest.approx(0.03)
    assert s[2] == pytest.approx(np.hypot(m.default_error_m, 0.02))


def test_model_options_are_validated():
    with pytest.raises(OptionError):
        VisualSensorModel(fusion_weight=0.0)
    with pytest.raises(OptionError):
        VisualSensorModel(margin_sigmas=-1)
    with pytest.raises(OptionError):
        VisualSensorModel(free_a=float("nan"))


def test_output_calibration_maps_log_odds_to_probabilities_not_decisions():
    opts = AvoidanceMapOptions(
        size_m=1.0,
        cell_size_m=0.1,
        probability_scale=0.5,
        probability_offset=-1.0,
        probability_knots=None,
    )
    m = AvoidanceMap(opts)
    layer = m.log_odds
    layer[0, :3] = (4.0, 1.0, -1.5)
    m.log_odds = m.plan_log_odds = layer  # the map's evidence and the planner's
    p = m.probabilities()
    assert p[0, 0] == pytest.approx(1 / (1 + np.exp(-(0.5 * 4.0 - 1.0))))
    assert p[5, 5] == 0.5  # no evidence: unknown, whatever the calibration
    classes = m.occupancy_classes()
    # decisions come from the raw evidence: logit(0.65) = 0.62, logit(0.196) = -1.41
    assert classes[0].tolist()[:3] == [2, 2, 0] and classes[5, 5] == 1
    assert m.occupied()[0, 1]
