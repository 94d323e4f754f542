"""Calibration at the command line's default 8 px table spacing and on other lenses than the
simulator's default, against the simulator's exact image-to-ground mapping: max <= 1 cm and
RMS <= 0.5 cm within 3 m (the issue's bound; the paper's is 2 cm)."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan import CameraMount, Lens
from floorscan.calibration import Pattern, calibrate
from floorscan.sim import CalibrationPattern, Camera, render_calibration

LENSES = {
    "wide": (None, None),  # the simulator's Kannala-Brandt, about 136 degrees
    # A 180-degree equidistant fisheye, mounted low: a board in its corners.
    "fisheye": (
        Lens.equidistant(f=200.0, cx=322.0, cy=236.0),
        CameraMount(height_m=0.3, tilt_rad=0.7),
    ),
    # A Duckiebot-like wide-angle lens (OpenCV plumb_bob), and a distortion-free one.
    "plumb_bob": (
        Lens.pinhole_radial(
            fx=295.8, fy=299.5, cx=321.3, cy=241.7, k1=-0.2354, k2=0.0364, p1=-0.0033, p2=-0.0012
        ),
        CameraMount(height_m=0.35, tilt_rad=0.45),
    ),
    "pinhole": (
        Lens.pinhole(fx=500.0, fy=500.0, cx=319.5, cy=239.5),
        CameraMount(height_m=0.6, tilt_rad=0.5),
    ),
}


def scene(lens: str, kind: str, **pattern):
    lens_model, mount = LENSES[lens]
    cam = Camera(width=640, height=480, lens=lens_model, mount=mount)
    spec = CalibrationPattern(kind=kind, **pattern) if pattern else None
    image, spec = render_calibration(cam, spec, kind=kind)
    return cam, image, Pattern.from_toml(spec.to_toml())


def errors(cam: Camera, table) -> np.ndarray:
    v, u = np.mgrid[0 : cam.height, 0 : cam.width].astype(np.float64)
    x, y = table.lookup(u, v)
    tx, ty = cam.pixel_to_ground(u, v)
    ok = np.isfinite(x) & np.isfinite(tx) & (np.hypot(tx, ty) < 3.0)
    return np.hypot(x - tx, y - ty)[ok]


def assert_within_1_cm(e: np.ndarray, min_pixels: int) -> None:
    assert e.size >= min_pixels, f"the table covers {e.size} pixels"
    assert e.max() <= 0.01, f"max error {100 * e.max():.2f} cm"
    assert np.sqrt(np.mean(e**2)) <= 0.005


@pytest.mark.parametrize(
    "lens, kind, pattern",
    [
        ("wide", "lines", {}),
        ("wide", "lines", {"near_left": (0.15, 0.55), "yaw": 0.15}),
        ("wide", "lines", {"near_left": (0.17, 0.45), "yaw": -0.15}),
        ("fisheye", "checkerboard", {"near_left": (0.22, 0.40)}),
        ("plumb_bob", "lines", {"near_left": (0.30, 0.375), "lines": (6, 6), "spacing": 0.15}),
        ("pinhole", "checkerboard", {"near_left": (0.95, 0.40)}),
    ],
)
def test_default_spacing_within_1_cm(lens, kind, pattern):
    cam, image, pat = scene(lens, kind, **pattern)
    table, report = calibrate(image, pat, near_field=False, coverage="pattern")  # 8 px nodes
    assert report.points_found >= pat.point_count - 6
    assert_within_1_cm(errors(cam, table), 30_000)


def test_line_crossings_to_a_tenth_of_a_pixel():
    """The crossings of the simulator's line grid, against where its lens puts them."""
    cam, image, pat = scene("wide", "lines")
    _, report = calibrate(image, pat)
    g = report.ground_points
    truth = np.stack(cam.ground_to_pixel(g[:, 0], g[:, 1]), axis=-1)
    e = np.linalg.norm(report.image_points - truth, axis=1)
    assert np.sqrt(np.mean(e**2)) <= 0.15 and e.max() <= 0.6


def test_a_distortion_free_lens_extrapolates_almost_exactly():
    cam, image, pat = scene("pinhole", "checkerboard", near_left=(0.95, 0.40))
    table, _ = calibrate(image, pat, extrapolate=True)
    e = errors(cam, table)
    assert e.size > 100_000 and e.max() <= 0.01
