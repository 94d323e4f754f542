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


OVERLAY_GREY_LEVELS = 252
"""Grey levels of :data:`OVERLAY_PALETTE` (entries 0..251, black to white); entries 252..255
are the :data:`STATUS_COLOURS` in their order."""


def _overlay_palette() -> np.ndarray:
    n = OVERLAY_GREY_LEVELS
    palette = np.zeros((256, 3), dtype=np.uint8)
    palette[:n] = np.round(np.arange(n) * 255 / (n - 1)).astype(np.uint8)[:, None]
    palette[n:] = list(STATUS_COLOURS.values())
    return palette


OVERLAY_PALETTE = _overlay_palette()
"""The (256, 3) uint8 RGB palette of :func:`draw_scan_overlay_indexed`: one palette for every
frame of an animation, so an overlay GIF needs no per-frame colour quantisation."""

STATUS_INDEX = {name: OVERLAY_GREY_LEVELS + k for k, name in enumerate(STATUS_COLOURS)}
"""Palette index of each status colour in :data:`OVERLAY_PALETTE`."""

_GREY_INDEX = np.round(np.arange(256) * (OVERLAY_GREY_LEVELS - 1) / 255).astype(np.uint8)


def _grey8(image: np.ndarray) -> np.ndarray:
    grey = as_grey(image)
    return (grey >> 8).astype(np.uint8) if grey.dtype == np.uint16 else grey


def draw_scan_overlay(
    image: np.ndarray, scan: Scan, *, truth_rows: Optional[np.ndarray] = None
) -> np.ndarray:
    """An RGB uint8 copy of ``image`` with the scan drawn on it (and, if given, the true
    boundary rows per sampled column as small white dashes)."""
    from PIL import Image, ImageDraw

    grey = _grey8(image)
    canvas = Image.fromarray(np.stack([grey] * 3, axis=-1))
    draw = ImageDraw.Draw(canvas)
    _draw_marks(draw, scan, grey.shape, STATUS_COLOURS)
    if truth_rows is not None:
        radius = _radius(grey.shape)
        for u, t in zip(scan.columns, np.asarray(truth_rows, dtype=float)):
            if np.isfinite(t):
                draw.line(
                    [float(u) - radius, t, float(u) + radius, t], fill=(255, 255, 255), width=1
                )
    return np.asarray(canvas)


def draw_scan_overlay_indexed(
    image: np.ndarray, scan: Scan, *, max_width: Optional[int] = None
) -> np.ndarray:
    """:func:`draw_scan_overlay` as (H, W) uint8 indices into :data:`OVERLAY_PALETTE` (grey
    rounded to its 252 levels, the marks in the same places and colours): frames for an
    animation that shares one palette. With ``max_width``, the image is halved (every other
    row and column) while wider than it, and the marks are drawn on the smaller picture."""
    from PIL import Image, ImageDraw

    grey = _grey8(image)
    scale = 1.0
    while max_width is not None and grey.shape[1] > max_width:
        grey, scale = grey[::2, ::2], scale / 2
    canvas = Image.fromarray(np.take(_GREY_INDEX, grey))
    _draw_marks(ImageDraw.Draw(canvas), scan, grey.shape, STATUS_INDEX, scale)
    return np.asarray(canvas)


def _radius(shape) -> int:
    return max(2, round(min(shape) / 80))


def _draw_marks(draw, scan: Scan, shape, colours, scale: float = 1.0) -> None:
    """Each column's mark, in ``colours[status name]`` (RGB tuples or palette indices), on a
    picture of ``shape`` (H, W) that is the image scaled by ``scale``."""
    h, w = shape
    radius = _radius(shape)
    rows = scan.rows * scale
    starts = scan._native.start_rows * scale
    for u, v, name, start in zip(scan.columns, rows, scan.status, starts):
        colour = colours[name]
        u = float(u) * scale
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
