"""Scoring functions: zero error on the truth itself, the right error on known perturbations."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import Scan
from floorscan.evaluation.scoring import score_columns, score_map, summarise_columns


def truth_and_scan(shift_m=0.0, flip=None):
    w = 10
    status = np.zeros(w, np.uint8)
    status[7] = 1  # no boundary
    pts = np.stack([np.linspace(0.5, 3.5, w), np.zeros(w)], axis=1)
    cols = np.arange(w)
    sx = pts[:, 0] + shift_m
    st = status.copy()
    if flip is not None:
        st[flip] = 1  # no boundary, though the columns scanned 1 m past the true boundary
        sx[flip] += 1.0
    scan = Scan.from_arrays(
        timestamp=0, columns=cols, rows=np.full(w, 10.0), status=st, x=sx, y=pts[:, 1]
    )
    return scan, status, pts


def test_truth_itself_scores_zero():
    scan, status, pts = truth_and_scan()
    s = score_columns(scan, status, pts)
    assert not s.wrong.any()
    summary = summarise_columns([s])
    assert summary.error_rate == 0 and summary.far_point_share == 0 and summary.median_error_cm == 0


def test_shifted_boundary_and_flipped_status_are_counted():
    scan, status, pts = truth_and_scan(shift_m=0.05)
    summary = summarise_columns([score_columns(scan, status, pts)])
    assert summary.error_rate == 0 and summary.median_error_cm == pytest.approx(5.0)
    scan, status, pts = truth_and_scan(shift_m=0.15)
    summary = summarise_columns([score_columns(scan, status, pts)])
    assert summary.error_rate == pytest.approx(0.9)  # the 9 boundary columns are 15 cm off
    scan, status, pts = truth_and_scan(flip=[2, 3])
    summary = summarise_columns([score_columns(scan, status, pts)])
    assert summary.error_rate == pytest.approx(0.2)
    assert summary.by_range["0-1 m"]["points"] == 2  # true ranges 0.5 and 0.83 m


def test_map_scores_count_a_flipped_cell():
    truth = np.zeros((4, 5), np.int8)
    truth[0, :] = 100
    truth[3, 4] = -1
    classes = np.where(truth == 100, 2, 0).astype(np.uint8)
    s = score_map(classes, (0.0, 0.0), 0.1, truth, (0.0, 0.0), 0.1)
    assert (
        s.agreement == 1.0
        and s.known_cells == 19
        and s.occupied_precision == 1
        and s.occupied_recall == 1
    )
    classes[2, 2] = 2  # one false obstacle
    classes[0, 0] = 1  # one unknown
    s = score_map(classes, (0.0, 0.0), 0.1, truth, (0.0, 0.0), 0.1)
    assert s.known_cells == 18
    assert s.agreement == pytest.approx(17 / 18)
    assert s.occupied_precision == pytest.approx(4 / 5) and s.occupied_recall == 1.0
    # A map at twice the resolution samples the truth at its cell centres.
    fine = np.kron(np.where(truth == 100, 2, 0), np.ones((2, 2), int)).astype(np.uint8)
    s = score_map(fine, (0.0, 0.0), 0.05, truth, (0.0, 0.0), 0.1)
    assert s.agreement == 1.0 and s.known_cells == 19 * 4


def test_a_boundary_beyond_the_range_limit_is_not_a_miss():
    # Truth: boundary at 3.5 m. The scan stopped at 3.0 m (no_boundary, farthest point 3.0 m).
    truth_status = np.array([0, 0], np.uint8)
    truth_pts = np.array([[3.5, 0.0], [2.0, 0.0]])
    scan = Scan.from_arrays(
        timestamp=0,
        columns=[0, 1],
        rows=[5.0, 5.0],
        status=["no_boundary", "no_boundary"],
        x=[3.0, 3.0],
        y=[0.0, 0.0],
    )
    s = score_columns(scan, truth_status, truth_pts)
    assert list(s.wrong) == [False, True]  # the second column missed a boundary at 2 m
