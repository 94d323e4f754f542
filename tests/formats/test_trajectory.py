"""TUM trajectories, interpolation and the rig file."""

from __future__ import annotations

import math

import floorscan
import pytest
from floorscan.formats.rig import Rig, read_rig, write_rig
from floorscan.formats.trajectory import (
    Trajectory,
    quaternion_from_yaw,
    read_tum,
    write_tum,
    yaw_from_quaternion,
)


def test_tum_round_trip(tmp_path):
    tr = Trajectory([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], [0.0, -0.5, 0.25], [0.0, 3.0, -3.0])
    back = read_tum(write_tum(tmp_path / "odometry.txt", tr))
    assert list(back.timestamps) == pytest.approx([0.0, 0.1, 0.2])
    assert list(back.y) == pytest.approx([0.0, -0.5, 0.25])
    for a, b in zip(back.yaw, tr.yaw):
        assert math.remainder(a - b, 2 * math.pi) == pytest.approx(0.0, abs=1e-8)


@pytest.mark.parametrize("yaw", [0.0, 0.3, -2.0, 3.1])
def test_quaternion_yaw_round_trip(yaw):
    assert yaw_from_quaternion(*quaternion_from_yaw(yaw)) == pytest.approx(yaw)


def test_interpolation_takes_the_short_way_round_and_never_extrapolates():
    tr = Trajectory([1.0, 2.0], [0.0, 2.0], [0.0, 4.0], [3.0, -3.0])  # yaw wraps through pi
    p = tr.pose_at(1.5)
    assert (p.x, p.y) == pytest.approx((1.0, 2.0))
    assert abs(p.yaw) == pytest.approx(math.pi, abs=1e-9)
    assert tr.pose_at(0.99) is None and tr.pose_at(2.01) is None
    assert tr.pose_at(2.0).x == pytest.approx(2.0)


def test_bad_tum_lines_name_the_line(tmp_path):
    p = tmp_path / "t.txt"
    p.write_text("# header\n0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 1\n")
    with pytest.raises(floorscan.DatasetError, match=":3:"):
        read_tum(p)
    p.write_text("0 0 0 0 0 0 0 1\n0 1 0 0 0 0 0 1\n")
    with pytest.raises(floorscan.DatasetError, match="does not increase"):
        read_tum(p)
    p.write_text("0 a 0 0 0 0 0 1\n")
    with pytest.raises(floorscan.DatasetError, match=":1:"):
        read_tum(p)


def test_rig_round_trip_and_errors(tmp_path):
    rig = Rig(x=0.1, y=-0.02, yaw=0.05, height=0.35)
    assert read_rig(write_rig(tmp_path / "rig.toml", rig)) == rig
    (tmp_path / "bad.toml").write_text("[camera]\nx = 0.1\nheigth = 0.3\n")
    with pytest.raises(floorscan.ConfigError, match="camera.heigth"):
        read_rig(tmp_path / "bad.toml")
    (tmp_path / "bad2.toml").write_text("[camera]\nx = 'far'\n")
    with pytest.raises(floorscan.ConfigError, match="camera.x"):
        read_rig(tmp_path / "bad2.toml")


def test_compose_places_a_mounted_frame_in_the_world():
    import numpy as np
    from floorscan.formats.trajectory import compose

    # a robot at (1, 2) facing +y, a camera 0.5 m ahead of it turned right by 90 degrees:
    # the camera sits at (1, 2.5), facing +x; a point 1 m ahead of it is at (2, 2.5)
    cam = compose((1.0, 2.0, np.pi / 2), (0.5, 0.0, -np.pi / 2))
    np.testing.assert_allclose(cam, (1.0, 2.5, 0.0), atol=1e-12)
    np.testing.assert_allclose(compose(cam, (1.0, 0.0, 0.0))[:2], (2.0, 2.5), atol=1e-12)
