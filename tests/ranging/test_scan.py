"""Scans: CSV contract and round trip, laser-scan binning (REP 117)."""

from __future__ import annotations

import math

import floorscan
import numpy as np
import pytest
from conftest import affine_table
from floorscan import SCAN_CSV_HEADER, Scan, VisualRanger, read_scans_csv, write_scans_csv


def sample_scans():
    h, w = 48, 64
    v = np.arange(h)[:, None]
    edge = 10 + (np.arange(w) % 20)
    image = np.where(v >= edge[None, :], 90, 180).astype(np.uint8)
    image[:, :8] = 90  # no edge in the left columns
    image[44:, 56:] = 180  # obstacle right at the bottom on the right: too close
    ranger = VisualRanger(affine_table(w, h, horizon=2.0), columns=16, threshold=20)
    return [ranger.scan(image, timestamp=t) for t in (0.0, 0.1)]


def test_csv_has_the_contract_header_and_round_trips(tmp_path):
    scans = sample_scans()
    assert {"boundary", "no_boundary", "too_close"} <= set(scans[0].status)
    path = write_scans_csv(tmp_path / "scans.csv", scans)
    lines = path.read_text().splitlines()
    assert lines[0] == SCAN_CSV_HEADER == "timestamp,column,row,status,x,y,range,bearing"
    assert len(lines) == 1 + sum(len(s) for s in scans)
    back = read_scans_csv(path)
    assert len(back) == 2
    for a, b in zip(scans, back):
        assert a.timestamp == b.timestamp
        np.testing.assert_array_equal(a.columns, b.columns)
        np.testing.assert_array_equal(a.status, b.status)
        np.testing.assert_array_equal(a.rows, b.rows)
        np.testing.assert_array_equal(a.ranges, b.ranges)
        np.testing.assert_array_equal(a.x, b.x)


def test_rep117_ranges_in_csv():
    scan = sample_scans()[0]
    by_status = {s: r for s, r in zip(scan.status, scan.ranges)}
    assert by_status["no_boundary"] == math.inf
    assert by_status["too_close"] == -math.inf
    assert math.isfinite(by_status["boundary"])


def test_malformed_csv_names_the_line(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text(SCAN_CSV_HEADER + "\n0,1,2,boundary,1,0,1,0\n0,1,2,boundary,1\n")
    with pytest.raises(floorscan.FileFormatError, match=":3:"):
        read_scans_csv(p)
    p.write_text("time,col\n")
    with pytest.raises(floorscan.FileFormatError, match="header"):
        read_scans_csv(p)
    p.write_text(SCAN_CSV_HEADER + "\n0,1,2,sideways,1,0,1,0\n")
    with pytest.raises(floorscan.FileFormatError, match="sideways"):
        read_scans_csv(p)


def test_laser_scan_bins_hold_the_nearest_point():
    # Three boundary points at bearings 0.01, 0.02 (nearer), 0.21; one free column at 0.1.
    pts = [(2.0, 0.01), (1.5, 0.02), (1.0, 0.21), (3.0, 0.1)]
    x = [r * math.cos(b) for r, b in pts]
    y = [r * math.sin(b) for r, b in pts]
    scan = Scan.from_arrays(
        timestamp=0.0,
        columns=[0, 1, 2, 3],
        rows=[10.0] * 4,
        status=["boundary", "boundary", "boundary", "no_boundary"],
        x=x,
        y=y,
    )
    ls = scan.to_laser_scan(angle_min=0.0, angle_max=0.3, angle_increment=0.1)
    assert ls["ranges"][0] == pytest.approx(1.5)
    assert ls["ranges"][1] == math.inf
    assert ls["ranges"][2] == pytest.approx(1.0)
    assert ls["ranges"][3] == math.inf
    with pytest.raises(floorscan.OptionError):
        scan.to_laser_scan(angle_min=0.3, angle_max=0.0, angle_increment=0.1)


def test_from_arrays_checks_lengths_and_points():
    with pytest.raises(floorscan.LengthMismatchError):
        Scan.from_arrays(
            timestamp=0, columns=[1, 2], rows=[1.0], status=["boundary"], x=[1.0], y=[0.0]
        )
    with pytest.raises(floorscan.GeometryError):
        Scan.from_arrays(
            timestamp=0, columns=[1], rows=[1.0], status=["boundary"], x=[np.nan], y=[0.0]
        )


def test_column_status_enum_names_the_codes_of_scans():
    """`ColumnStatus` (from the Rust enum) names exactly the codes a scan carries and the
    documented CSV statuses (docs/formats.md), in code order."""
    assert [s.name.lower() for s in floorscan.ColumnStatus] == [
        "boundary",
        "no_boundary",
        "too_close",
        "invalid",
    ]
    for scan in sample_scans():
        names = [floorscan.ColumnStatus(int(c)).name.lower() for c in scan.status_codes]
        assert names == list(scan.status)
        boundary = scan.status_codes == floorscan.ColumnStatus.BOUNDARY
        assert np.all(np.isfinite(scan.x[boundary]))
