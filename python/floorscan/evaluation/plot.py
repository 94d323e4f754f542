"""A small line plot drawn with PIL (no matplotlib): error rate against threshold, one line per
half-width."""

from __future__ import annotations

from pathlib import Path
from typing import Dict, Optional, Sequence

import numpy as np

from ..image_io import write_png

PALETTE = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
]


def plot_curves(
    path: Path,
    x: Sequence[float],
    curves: Dict[str, Sequence[float]],
    *,
    title: str,
    x_label: str,
    y_label: str,
    marker: Optional[tuple] = None,
    vline: Optional[tuple] = None,
    size: tuple = (720, 440),
) -> Path:
    """Writes a PNG with one polyline per curve (y in [0, 1] shown in percent), axes with
    ticks, a legend, an optional ``marker`` (x, y, text) and vertical line (x, text)."""
    from PIL import Image, ImageDraw

    w, h = size
    left, right, top, bottom = 60, 150, 30, 45
    img = Image.new("RGB", (w, h), (255, 255, 255))
    draw = ImageDraw.Draw(img)
    xs = np.asarray(x, dtype=float)
    ys_all = np.concatenate([np.asarray(v, dtype=float) for v in curves.values()])
    ys_all = ys_all[np.isfinite(ys_all)]
    y_max = max(0.05, float(ys_all.max()) if ys_all.size else 1.0)
    y_max = min(1.0, np.ceil(y_max * 20) / 20)
    x0, x1 = float(xs.min()), float(xs.max()) if xs.max() > xs.min() else float(xs.min()) + 1
    pw, ph = w - left - right, h - top - bottom

    def px(xv: float, yv: float) -> tuple:
        return (left + (xv - x0) / (x1 - x0) * pw, top + (1 - yv / y_max) * ph)

    draw.rectangle([left, top, left + pw, top + ph], outline=(0, 0, 0))
    for t in np.linspace(0, y_max, 6):
        _, yy = px(x0, t)
        draw.line([left - 4, yy, left, yy], fill=(0, 0, 0))
        draw.line([left, yy, left + pw, yy], fill=(230, 230, 230))
        draw.text((6, yy - 6), f"{100 * t:.0f}%", fill=(0, 0, 0))
    for t in np.linspace(x0, x1, 9):
        xx, _ = px(t, 0)
        draw.line([xx, top + ph, xx, top + ph + 4], fill=(0, 0, 0))
        draw.text((xx - 8, top + ph + 6), f"{t:g}", fill=(0, 0, 0))
    draw.text((left + pw / 2 - 40, h - 18), x_label, fill=(0, 0, 0))
    draw.text((6, 8), f"{title}   ({y_label})", fill=(0, 0, 0))
    for i, (name, ys) in enumerate(curves.items()):
        colour = PALETTE[i % len(PALETTE)]
        pts = [px(a, b) for a, b in zip(xs, np.asarray(ys, dtype=float)) if np.isfinite(b)]
        if len(pts) > 1:
            draw.line(pts, fill=colour, width=2)
        ly = top + 14 * i + 4
        draw.line([left + pw + 10, ly + 6, left + pw + 30, ly + 6], fill=colour, width=3)
        draw.text((left + pw + 34, ly), name, fill=(0, 0, 0))
    if vline is not None:
        xx, _ = px(vline[0], 0)
        draw.line([xx, top, xx, top + ph], fill=(120, 120, 120), width=1)
        draw.text((xx + 3, top + 3), vline[1], fill=(90, 90, 90))
    if marker is not None:
        mx, my = px(marker[0], marker[1])
        draw.ellipse([mx - 5, my - 5, mx + 5, my + 5], outline=(0, 0, 0), width=2)
        draw.text((mx + 7, my - 14), marker[2], fill=(0, 0, 0))
    return write_png(path, np.asarray(img))
