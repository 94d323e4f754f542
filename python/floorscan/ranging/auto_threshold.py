"""A label-free edge threshold (beyond the paper): a multiple of the carpet's texture noise as
the box filter sees it, measured in the rows nearest the robot (floor by the paper's own
assumption that the bottom of the image is carpet). Adapts the threshold to the carpet, the
camera's noise and the lighting, where a fixed threshold must be re-tuned by hand.

Measured against ``floorscan tune``'s optimum in EVALUATION.md.
"""

from __future__ import annotations

from typing import Sequence, Tuple

import numpy as np

from ..errors import OptionError

AUTO_K = 5.0
"""Default multiple of the robust texture-noise estimate."""
MIN_AUTO_THRESHOLD = 2.0
"""Lowest automatic threshold (intensity units): a noise-free image must not make every
one-level step an edge."""


def texture_noise(
    images: Sequence[np.ndarray],
    *,
    half_width: int,
    columns: Sequence[int],
    bottom_margin: int,
    rows_fraction: float = 0.12,
) -> float:
    """Robust standard deviation (1.4826 MAD) of the box filter response R (half the
    difference of the window means, as the ranger computes it) over the rows nearest the robot
    (the bottom ``rows_fraction`` of the image above ``bottom_margin``): the carpet's texture
    and the sensor noise as the filter sees them, with no labels."""
    d = int(half_width)
    samples = []
    cols = np.asarray(columns, dtype=np.intp)
    for image in images:
        img = np.asarray(image, dtype=np.float64)
        if np.asarray(image).dtype == np.uint16:
            img /= 257.0  # 8-bit intensity units, as the threshold (see VisualRanger)
        h = img.shape[0]
        bottom = h - 1 - bottom_margin  # lowest row scanned
        top = max(d, bottom - max(2 * d + 1, int(round(rows_fraction * h))))
        c = np.cumsum(np.vstack([np.zeros((1, cols.size)), img[:, cols]]), axis=0)
        for v in range(top + d, bottom - d + 1):
            above = c[v] - c[v - d]  # rows v-d .. v-1 (image rows above v)
            below = c[v + d + 1] - c[v + 1]  # rows v+1 .. v+d
            samples.append((above - below) / (2 * d))
    if not samples:
        raise OptionError("images too small for the texture-noise estimate")
    r = np.concatenate(samples)
    return float(1.4826 * np.median(np.abs(r - np.median(r))))


def auto_threshold(
    images: Sequence[np.ndarray],
    *,
    half_width: int,
    columns: Sequence[int],
    k: float = AUTO_K,
    bottom_margin: int,
) -> Tuple[float, float]:
    """(threshold, noise): ``k`` times :func:`texture_noise`."""
    noise = texture_noise(
        images, half_width=half_width, columns=columns, bottom_margin=bottom_margin
    )
    return k * noise, noise
