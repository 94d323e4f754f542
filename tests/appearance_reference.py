"""The appearance ranger's method written independently with numpy (whole-image arrays, no
shared code with the Rust core): the brute-force reference of tests/ranging/test_appearance.py and the
side-by-side baseline of bench/appearance_vs_numpy.py. Ground everywhere, columns scanned from
``start_row`` to the top row."""

from __future__ import annotations

import numpy as np

I_BINS, C_BINS, T_BINS = 16, 12, 8


def colour_bins(rgb: np.ndarray) -> np.ndarray:
    r, g, b = (rgb[..., c].astype(np.int32) for c in range(3))
    i = ((r + g + b) // 3) >> 4
    c1 = np.clip(r - g + 96, 0, 16 * C_BINS - 1) >> 4
    c2 = np.clip((r + g) // 2 - b + 96, 0, 16 * C_BINS - 1) >> 4
    return (i * C_BINS + c1) * C_BINS + c2


def texture_bins(rgb: np.ndarray) -> np.ndarray:
    g = rgb[..., 1].astype(np.int32)
    p = np.pad(g, 1, mode="edge")
    grad = np.abs(p[1:-1, 2:] - p[1:-1, :-2]) + 2 * np.abs(p[2:, 1:-1] - p[1:-1, 1:-1])
    return np.minimum(grad >> 3, T_BINS - 1)


def _box(counts: np.ndarray, axis: int, reach: int) -> np.ndarray:
    n = counts.shape[axis]
    c = np.cumsum(np.moveaxis(counts, axis, 0), axis=0)
    c = np.concatenate([np.zeros_like(c[:1]), c])
    idx = np.arange(n)
    hi = np.minimum(idx + reach, n - 1) + 1
    lo = np.maximum(idx - reach, 0)
    return np.moveaxis(c[hi] - c[lo], 0, axis)


def floor_lookup(rgb, start_row, band_rows, min_share, intensity_reach, width_fraction=0.5):
    """Boolean floor tables (colour bins, texture bins) learned from one frame's reference:
    every second row of the band and every second (even) column of its centred span."""
    h, w = rgb.shape[:2]
    rows = np.arange(start_row, max(start_row + 1 - band_rows, 0) - 1, -2)
    n_cols = min(max(int(np.floor(width_fraction * w + 0.5)), 1), w)
    lo = (w - n_cols) // 2
    cols = np.array([u for u in range(0, w, 2) if lo <= u < lo + n_cols])
    ref = rgb[rows][:, cols]
    cb = colour_bins(ref).ravel()
    tb = texture_bins(rgb)[rows][:, cols].ravel()
    n = cb.size
    hist = np.bincount(cb, minlength=I_BINS * C_BINS * C_BINS).reshape(I_BINS, C_BINS, C_BINS)
    hist = _box(_box(_box(hist, 2, 1), 1, 1), 0, intensity_reach)
    th = _box(np.bincount(tb, minlength=T_BINS), 0, 1)
    return (hist.ravel().astype(np.float32) / np.float32(n)) >= np.float32(min_share), (
        th.astype(np.float32) / np.float32(n)
    ) >= np.float32(min_share)


def appearance_scan(
    rgb: np.ndarray,
    columns: np.ndarray,
    *,
    start_row: int,
    reference_fraction: float = 0.1,
    reference_width_fraction: float = 0.5,
    min_share: float = 0.003,
    intensity_reach: int = 1,
    patch_half_width: int = 2,
    min_run: int = 3,
    texture: bool = True,
):
    """(status codes, rows) per column: 0 boundary (row = lowest non-floor row + 0.5),
    1 no_boundary (row 0), 2 too_close (row = start_row)."""
    h, w = rgb.shape[:2]
    band = max(int(round(reference_fraction * h)), 1)
    lut_c, lut_t = floor_lookup(
        rgb, start_row, band, min_share, intensity_reach, reference_width_fraction
    )
    floor = lut_c[colour_bins(rgb)]
    if texture:
        floor &= lut_t[texture_bins(rgb)]
    # Per column: floor count over the patch, per row; not floor when most are not.
    c = np.cumsum(np.pad(floor, ((0, 0), (1, 0))).astype(np.int32), axis=1)
    a = np.maximum(columns - patch_half_width, 0)
    b = np.minimum(columns + patch_half_width, w - 1)
    count = c[:, b + 1] - c[:, a]
    not_floor = 2 * count < (b - a + 1)[None, :]
    nf = not_floor[: start_row + 1][::-1]  # k = 0 at start_row
    run = nf.copy()
    for i in range(1, min_run):
        run[: len(nf) - i] &= nf[i:]
        run[len(nf) - i :] = False
    has = run.any(axis=0)
    k = run.argmax(axis=0)
    status = np.where(has, np.where(k == 0, 2, 0), 1)
    rows = np.where(status == 0, start_row - k + 0.5, np.where(status == 2, start_row, 0.0))
    return status.astype(np.uint8), rows
