"""The pattern.toml contract (docs/calibration.md): the simulator's files read back exactly,
round trips, geometry of the points, and errors that name the field."""

from __future__ import annotations

import math

import numpy as np
import pytest
from floorscan import ConfigError
from floorscan.calibration import Pattern, PatternKind
from floorscan.sim import CalibrationPattern, Camera


@pytest.mark.parametrize("kind", ["checkerboard", "lines"])
def test_simulator_pattern_files_read_back_with_the_same_points(kind):
    spec = CalibrationPattern.default_for(Camera(), kind=kind)
    p = Pattern.from_toml(spec.to_toml())
    assert p.kind is PatternKind(kind)
    np.testing.assert_allclose(p.points(), spec.points(), atol=1e-12)


def test_round_trip_and_geometry(tmp_path):
    p = Pattern.checkerboard(inner_corners=(4, 3), square=0.05, near_left=(0.5, 0.2), yaw=0.3)
    back = Pattern.load(p.save(tmp_path / "pattern.toml"))
    assert back == p
    pts = p.points()
    assert pts.shape == (12, 2)
    np.testing.assert_allclose(pts[0], (0.5, 0.2))
    # Row by row away from the camera, left to right: the second point is one square along
    # the across axis (sin yaw, -cos yaw); the fifth starts the next row, one square away.
    np.testing.assert_allclose(pts[1] - pts[0], 0.05 * np.array([math.sin(0.3), -math.cos(0.3)]))
    np.testing.assert_allclose(pts[4] - pts[0], 0.05 * np.array([math.cos(0.3), math.sin(0.3)]))
    lines = Pattern.from_toml(
        'kind = "lines"\nspacing = 0.2\nlines = [7, 9]\nnear_left = [0.45, 0.6]\n'
    )
    assert lines.line_width_m == 0.02 and lines.yaw == 0.0 and lines.point_count == 63
    assert Pattern.from_toml(lines.to_toml()) == lines


@pytest.mark.parametrize(
    "text, field",
    [
        ("inner_corners = [9, 7]\nsquare = 0.1\nnear_left = [0.4, 0.4]", "kind"),
        ('kind = "dots"\nnear_left = [0.4, 0.4]', "kind"),
        ('kind = "checkerboard"\nsquare = 0.1\nnear_left = [0.4, 0.4]', "inner_corners"),
        ('kind = "checkerboard"\ninner_corners = [9, 7]\nnear_left = [0.4, 0.4]', "square"),
        ('kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = 0.1', "near_left"),
        (
            'kind = "checkerboard"\ninner_corners = [9.5, 7]\nsquare = 0.1\nnear_left = [0, 0]',
            "inner_corners",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7, 3]\nsquare = 0.1\nnear_left = [0, 0]',
            "inner_corners",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [1, 7]\nsquare = 0.1\nnear_left = [0, 0]',
            "inner_corners",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = "10cm"\nnear_left = [0, 0]',
            "square",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = -0.1\nnear_left = [0, 0]',
            "square",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = 0.1\nnear_left = [0, "a"]',
            "near_left",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = 0.1\nnear_left = [0, 0]\nyaw = true',
            "yaw",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = 0.1\nnear_left = [0, 0]\nspacing = 0.2',
            "spacing",
        ),
        (
            'kind = "checkerboard"\ninner_corners = [9, 7]\nsquare = 0.1\nnear_left = [0, 0]\ncolour = 1',
            "colour",
        ),
        ('kind = "lines"\nlines = [7, 9]\nnear_left = [0, 0]', "spacing"),
        (
            'kind = "lines"\nspacing = 0.2\nlines = [7, 9]\nnear_left = [0, 0]\nline_width = 0.5',
            "line_width",
        ),
        (
            'kind = "lines"\nspacing = 0.2\nlines = [7, 9]\nnear_left = [0, 0]\nsquare = 0.1',
            "square",
        ),
    ],
)
def test_bad_fields_are_config_errors_naming_the_field(text, field):
    with pytest.raises(ConfigError, match=f"`{field}`"):
        Pattern.from_toml(text, source="pattern.toml")


def test_unreadable_files_are_config_errors(tmp_path):
    with pytest.raises(ConfigError, match="cannot read"):
        Pattern.load(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("kind = \n")
    with pytest.raises(ConfigError, match="invalid TOML"):
        Pattern.load(bad)
