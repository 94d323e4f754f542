"""Real CARMEN logs of real buildings (../shared/data/carmen, see its README): parsing, and maps
checked against the maps their publishers rendered. Skipped where the data is absent."""

import dataclasses
import gzip
import math

import numpy as np
import pytest
from conftest import shared_data_dir
from floorscan import OccupancyGrid
from floorscan.commands.map_log import map_lasers
from floorscan.formats.carmen import read_carmen

CARMEN = shared_data_dir() / "carmen"
pytestmark = pytest.mark.skipif(
    not CARMEN.is_dir(), reason=f"real CARMEN logs not found at {CARMEN} (set FLOORSCAN_DATA)"
)


def first_line(name: str, kind: str) -> list:
    with gzip.open(CARMEN / name, "rt") as f:
        for lineno, line in enumerate(f, start=1):
            if line.startswith(kind + " "):
                return [lineno] + line.split()
    raise AssertionError(f"no {kind} line in {name}")


def test_freiburg_log_parses_completely():
    log = read_carmen(CARMEN / "freiburg-079-corrected.log.gz")
    assert (len(log.lasers), len(log.odometry)) == (4791, 9725)
    assert log.skipped == {"PARAM": 187, "NEFF": 4791} and log.bad_lines == []
    lineno, _, n, *rest = first_line("freiburg-079-corrected.log.gz", "FLASER")
    r = log.lasers[0]
    assert r.line == lineno and r.ranges.size == int(n) == 360
    np.testing.assert_array_equal(r.ranges, np.array(rest[:360], dtype=float))
    assert r.laser_pose == tuple(float(v) for v in rest[360:363])
    assert r.timestamp == float(rest[366])


def test_csail_robotlaser1_log_parses_completely():
    log = read_carmen(CARMEN / "csail-robotlaser1.log.gz")
    assert len(log.lasers) == 686 and log.bad_lines == []
    fields = first_line("csail-robotlaser1.log.gz", "ROBOTLASER1")[1:]
    r = log.lasers[0]
    assert (r.angle_min, r.angle_increment, r.max_range) == (
        float(fields[2]),
        float(fields[4]),
        float(fields[5]),
    )
    assert r.ranges.size == int(fields[8]) == 361
    assert r.laser_pose == tuple(float(v) for v in fields[-14:-11])


def endpoint_agreement(lasers, grid) -> float:
    """Fraction of measured end points (ranges < 40 m) that fall in occupied cells."""
    xs, ys = [], []
    for r in lasers[::5]:
        a = r.angle_min + np.arange(r.ranges.size) * r.angle_increment + r.laser_pose[2]
        ok = r.ranges < 40
        xs.append(r.laser_pose[0] + r.ranges[ok] * np.cos(a[ok]))
        ys.append(r.laser_pose[1] + r.ranges[ok] * np.sin(a[ok]))
    return float(np.mean(grid.is_occupied(np.concatenate(xs), np.concatenate(ys))))


def test_intel_map_is_sharp_with_the_right_beam_layout():
    # The scans come from corrected (SLAM) poses: with the right beam angles, the end points of
    # all scans pile up on the same wall cells. A wrong layout (pi / (n - 1) steps) blurs them.
    log = read_carmen(CARMEN / "intel-corrected.log.gz")
    right = OccupancyGrid()
    map_lasers(right, log.lasers, max_range_m=40.0, min_range_m=0.05)
    n = log.lasers[0].ranges.size
    shifted = [dataclasses.replace(r, angle_increment=math.pi / (n - 1)) for r in log.lasers]
    wrong = OccupancyGrid()
    map_lasers(wrong, shifted, max_range_m=40.0, min_range_m=0.05)
    good, bad = endpoint_agreement(log.lasers, right), endpoint_agreement(shifted, wrong)
    assert good > 0.68 and good > bad + 0.03, (good, bad)


@pytest.mark.parametrize("name", ["freiburg-079-corrected", "intel-corrected"])
def test_map_has_the_shape_of_the_published_map(name):
    from PIL import Image

    log = read_carmen(CARMEN / f"{name}.log.gz")
    grid = OccupancyGrid()
    map_lasers(grid, log.lasers, max_range_m=40.0, min_range_m=0.05)
    iy, ix = np.nonzero(grid.occupancy_classes() == 2)
    ours = np.ptp(np.percentile(ix, [0.5, 99.5])) / np.ptp(np.percentile(iy, [0.5, 99.5]))
    with Image.open(CARMEN / f"{name}.png") as im:
        published = np.asarray(im.convert("L"))
    py, px = np.nonzero(published < 100)
    theirs = np.ptp(px) / np.ptp(py)
    assert ours == pytest.approx(theirs, rel=0.05)
