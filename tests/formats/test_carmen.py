"""CARMEN log parsing: the three message types, gzip, and bad lines named by line number."""

import gzip
import math

import numpy as np
import pytest
from floorscan import DatasetError
from floorscan.cli import main
from floorscan.formats.carmen import parse_carmen_lines, read_carmen

FLASER = "FLASER 4 1.0 2.0 3.0 81.91 0.5 -0.25 0.1 0.6 -0.2 0.15 12.5 host 12.6"
ROBOTLASER1 = (
    "ROBOTLASER1 0 -1.570796 3.141593 0.785398 80.0 0.01 0 5 1.5 2.5 81.91 0.3 0.4 "
    "2 7.0 8.0 1.0 2.0 0.3 1.1 2.1 0.35 0.0 0.0 0.0 0.0 0.0 100.25 b21 0.5"
)
ODOM = "ODOM 0.1 0.2 0.3 0.4 0.5 0.0 42.0 host 42.1"


def test_flaser_fields_and_beam_layout():
    log = parse_carmen_lines([FLASER])
    (r,) = log.lasers
    assert r.kind == "FLASER" and r.line == 1 and r.timestamp == 12.5
    np.testing.assert_array_equal(r.ranges, [1.0, 2.0, 3.0, 81.91])
    assert r.laser_pose == (0.5, -0.25, 0.1) and r.robot_pose == (0.6, -0.2, 0.15)
    # 4 beams over 180 degrees from -90: steps of 45 degrees (even count: pi / n).
    assert r.angle_min == pytest.approx(-math.pi / 2) and r.angle_increment == pytest.approx(
        math.pi / 4
    )
    assert r.max_range is None
    odd = parse_carmen_lines(["FLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0"]).lasers[0]
    assert odd.angle_increment == pytest.approx(math.pi / 2)  # 181-style: both ends included


def test_robotlaser1_fields():
    (r,) = parse_carmen_lines([ROBOTLASER1]).lasers
    assert r.kind == "ROBOTLASER1" and r.max_range == 80.0
    np.testing.assert_array_equal(r.ranges, [1.5, 2.5, 81.91, 0.3, 0.4])
    assert r.angle_min == pytest.approx(-1.570796) and r.angle_increment == pytest.approx(0.785398)
    assert (
        r.laser_pose == (1.0, 2.0, 0.3)
        and r.robot_pose == (1.1, 2.1, 0.35)
        and r.timestamp == 100.25
    )


def test_odometry_and_other_lines():
    log = parse_carmen_lines(["# comment", "", "PARAM robot_x 1 h 0", ODOM, "NEFF 10", "NEFF 9"])
    (o,) = log.odometry
    assert (
        o.pose == (0.1, 0.2, 0.3)
        and (o.tv, o.rv) == (0.4, 0.5)
        and o.timestamp == 42.0
        and o.line == 4
    )
    assert log.skipped == {"PARAM": 1, "NEFF": 2}


@pytest.mark.parametrize(
    "line, message",
    [
        ("FLASER 4 1.0 2.0 3.0", "expected 15 fields, got 5"),
        ("FLASER 4 1.0 2.0 x 4.0 0 0 0 0 0 0 1 h 1", "range value is not a number: 'x'"),
        ("FLASER 2.5 1 1 0 0 0 0 0 0 1 h 1", "must be a count"),
        ("FLASER 2 1 nan 0 0 0 0 0 0 1 h 1", "NaN"),
        ("ODOM 1 2 3", "expected 10 fields, got 4"),
        ("ODOM 1 2 three 0 0 0 1 h 1", "field 3 (pose theta)"),
        (ROBOTLASER1.rsplit(" ", 3)[0], "expected 31 fields"),
    ],
)
def test_bad_lines_are_named_by_line_number(line, message):
    lines = [ODOM, "PARAM a b", line, ODOM]
    with pytest.raises(
        DatasetError, match=r"<log>:3: .*" + message.replace("(", r"\(").replace(")", r"\)")
    ):
        parse_carmen_lines(lines)
    log = parse_carmen_lines(lines, strict=False)
    assert [n for n, _ in log.bad_lines] == [3] and message in log.bad_lines[0][1]
    assert len(log.odometry) == 2


def test_reads_plain_and_gzip_files(tmp_path):
    text = "\n".join([FLASER, ODOM, ROBOTLASER1]) + "\n"
    (tmp_path / "a.log").write_text(text)
    with gzip.open(tmp_path / "a.log.gz", "wt") as f:
        f.write(text)
    (tmp_path / "b.clf").write_bytes(gzip.compress(text.encode()))  # gzip whatever the name
    for name in ("a.log", "a.log.gz", "b.clf"):
        log = read_carmen(tmp_path / name)
        assert [r.kind for r in log.lasers] == ["FLASER", "ROBOTLASER1"] and len(log.odometry) == 1
    with pytest.raises(DatasetError, match="missing.log"):
        read_carmen(tmp_path / "missing.log")
    (tmp_path / "bad.gz").write_bytes(b"\x1f\x8b" + b"garbage")
    with pytest.raises(DatasetError, match="bad.gz"):
        read_carmen(tmp_path / "bad.gz")


def test_a_corrupt_gzip_log_is_a_dataset_error_naming_it(tmp_path):
    """A gzip stream damaged in the middle (zlib's error, not OSError) is refused like any
    unreadable log: one DatasetError, and `map-log` exits 1, not 5 (internal error)."""
    data = gzip.compress(b"FLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0\n" * 200)
    path = tmp_path / "bad.log.gz"
    path.write_bytes(data[: len(data) // 2] + b"\x00garbage")
    with pytest.raises(DatasetError, match="cannot read CARMEN log .*bad.log.gz"):
        read_carmen(path)
    assert main(["map-log", str(path), "-o", str(tmp_path / "m.yaml")]) == 1
    assert not (tmp_path / "m.yaml").exists()
