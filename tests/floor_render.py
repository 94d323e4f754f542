"""Test-only renderer of calibration patterns lying on the floor, seen through floorscan's own lens
models (independent of the calibration code under test): each pixel is supersampled, each
sample's ground point comes from the exact camera model (``GroundTable.from_camera`` at one
pixel spacing), the pattern's albedo is evaluated there analytically, then blur and noise.

The truth of a rendering is the same exact mapping (:func:`exact_table`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import cv2
import floorscan
import numpy as np
from floorscan.calibration import Pattern, PatternKind

DARK = 0.06
LIGHT = 0.85
CARPET = 0.32


def wide_angle(width: int = 640, height: int = 480) -> Tuple[floorscan.Lens, floorscan.CameraMount]:
    """A Kannala-Brandt fisheye of about 136 degrees horizontal field of view, 0.40 m above the
    floor, tilted down 0.6 rad (the simulator's default camera)."""
    f = 135.0 * width / 320.0
    lens = floorscan.Lens.kannala_brandt(
        fx=f, fy=f, cx=(width - 1) / 2, cy=(height - 1) / 2, k1=-0.012, k2=0.002
    )
    return lens, floorscan.CameraMount(height_m=0.40, tilt_rad=0.6)


def exact_table(
    lens: floorscan.Lens, mount: floorscan.CameraMount, width: int, height: int
) -> floorscan.GroundTable:
    return floorscan.GroundTable.from_camera(
        lens, mount, image_width=width, image_height=height, spacing_px=1, max_range_m=50.0
    )


def albedo(pattern: Pattern, x: np.ndarray, y: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Floor albedo at ground points (x, y) [m]: the pattern on carpet."""
    across, away = pattern.axes()
    dx, dy = x - pattern.near_left[0], y - pattern.near_left[1]
    i = (dx * across[0] + dy * across[1]) / pattern.step_m
    j = (dx * away[0] + dy * away[1]) / pattern.step_m
    n_i, n_j = pattern.counts
    out = CARPET * (1.0 + 0.05 * rng.standard_normal(x.shape))
    if pattern.kind is PatternKind.CHECKERBOARD:
        sheet = (i > -1.5) & (i < n_i + 0.5) & (j > -1.5) & (j < n_j + 0.5)
        board = (i > -1) & (i < n_i) & (j > -1) & (j < n_j)
        dark = ((np.floor(i) + np.floor(j)) % 2 == 0) & board
        out = np.where(sheet, LIGHT, out)
        out = np.where(dark, DARK, out)
    else:
        half = pattern.line_width_m / 2 / pattern.step_m
        in_i = (i > -0.5) & (i < n_i - 0.5)
        in_j = (j > -0.5) & (j < n_j - 0.5)
        near_i = np.abs(i - np.clip(np.round(i), 0, n_i - 1)) < half
        near_j = np.abs(j - np.clip(np.round(j), 0, n_j - 1)) < half
        line = (near_i & in_j) | (near_j & in_i)
        out = np.where(line, DARK, out)
    return out


@dataclass
class Rendering:
    image: np.ndarray
    truth: floorscan.GroundTable
    pattern: Pattern


def render(
    pattern: Pattern,
    *,
    width: int = 640,
    height: int = 480,
    lens: Optional[floorscan.Lens] = None,
    mount: Optional[floorscan.CameraMount] = None,
    samples: int = 3,
    blur_sigma_px: float = 0.7,
    noise_dn: float = 2.0,
    brightness: float = 230.0,
    seed: int = 0,
) -> Rendering:
    """Renders ``pattern`` on carpet through the camera (default: :func:`wide_angle`)."""
    if lens is None or mount is None:
        lens, mount = wide_angle(width, height)
    truth = exact_table(lens, mount, width, height)
    rng = np.random.default_rng(seed)
    offsets = (np.arange(samples) + 0.5) / samples - 0.5
    acc = np.zeros((height, width))
    v0, u0 = np.mgrid[0:height, 0:width].astype(np.float64)
    for du in offsets:
        for dv in offsets:
            x, y = truth.lookup(u0 + du, v0 + dv)
            a = albedo(pattern, np.nan_to_num(x), np.nan_to_num(y), rng)
            acc += np.where(np.isfinite(x), a, 0.5)  # the wall above the horizon
    img = brightness * acc / samples**2
    if blur_sigma_px > 0:
        img = cv2.GaussianBlur(img, (0, 0), blur_sigma_px)
    img = img + noise_dn * rng.standard_normal(img.shape)
    return Rendering(np.clip(np.rint(img), 0, 255).astype(np.uint8), truth, pattern)


def angle_deg(a: float) -> float:
    return a * 180.0 / math.pi


def pixels_of_ground(truth: floorscan.GroundTable, points: np.ndarray) -> np.ndarray:
    """Pixels (u, v) that see ground points (M, 2) [m] under the exact mapping: the nearest
    table node, then Newton steps on the interpolated mapping. NaN where not found."""
    gx, gy = truth.nodes
    s = truth.spacing_px
    out = np.full((len(points), 2), np.nan)
    ok = np.isfinite(gx)
    vs, us = np.nonzero(ok)
    gxv, gyv = gx[ok], gy[ok]
    for k, (x, y) in enumerate(np.asarray(points, dtype=float)):
        n = np.argmin((gxv - x) ** 2 + (gyv - y) ** 2)
        p = np.array([us[n] * s, vs[n] * s], dtype=float)
        for _ in range(20):
            g = np.array(truth.lookup(*p), dtype=float) if truth.lookup(*p) else None
            if g is None:
                break
            h = 0.25
            gu = np.array(truth.lookup(p[0] + h, p[1])) - np.array(truth.lookup(p[0] - h, p[1]))
            gv = np.array(truth.lookup(p[0], p[1] + h)) - np.array(truth.lookup(p[0], p[1] - h))
            jac = np.column_stack([gu, gv]) / (2 * h)
            step = np.linalg.solve(jac, np.array([x, y]) - g)
            p = p + step
            if np.hypot(*step) < 1e-6:
                out[k] = p
                break
    return out
