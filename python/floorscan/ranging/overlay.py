"""Pictures of what the ranger saw: the image with each column's result marked, as in the
paper's Fig. 1b (boundary points circled)."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..formats.image_io import as_grey
from .scan import Scan

STATUS_COLOURS = {
    "boundary": (40, 220, 40),  # green circle at the boundary
    "no_boundary": (60, 140, 255),  # blue tick at the top row scanned: free as far as seen
    "too_close": (255, 60, 40),  # red cross at the start row: obstacle too close
    "invalid": (160, 160, 160),  # grey dot: no ground for this column
}


def draw_scan_overlay(
    image: np.ndarray, scan: Scan, *, truth_rows: Optional[np.ndarray] = None
) -> np.ndarray:
    """An RGB uint8 copy of ``image`` with the scan drawn on it (and, if given, the true
    boundary rows per sampled column as small white dashes)."""
    from PIL import Image, ImageDraw

    grey = as_grey(image)
    if grey.dtype == np.uint16:
        grey = (grey >> 8).astype(np.uint8)
    h, w = grey.shape
    canvas = Image.fromarray(np.stack([grey] * 3, axis=-1))
    draw = ImageDraw.Draw(canvas)
    radius = max(2, round(min(w, h) / 80))
    names = scan.status
    for u, v, name, start in zip(scan.columns, scan.rows, names, scan._native.start_rows):
        colour = STATUS_COLOURS[name]
        u = float(u)
        if name == "boundary":
            draw.ellipse(
                [u - radius, v - radius, u + radius, v + radius],
                outline=colour,
                width=max(1, radius // 2),
            )
        elif name == "no_boundary":
            draw.line([u, v, u, v + 2 * radius], fill=colour, width=2)
        elif name == "too_close":
            s = start if np.isfinite(start) else h - 1
            draw.line([u - radius, s - radius, u + radius, s + radius], fill=colour, width=2)
            draw.line([u - radius, s + radius, u + radius, s - radius], fill=colour, width=2)
        else:
            draw.point([u, h - 2], fill=colour)
    if truth_rows is not None:
        for u, t in zip(scan.columns, np.asarray(truth_rows, dtype=float)):
            if np.isfinite(t):
                draw.line(
                    [float(u) - radius, t, float(u) + radius, t], fill=(255, 255, 255), width=1
                )
    return np.asarray(canvas)
