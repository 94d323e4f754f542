"""Line plots (matplotlib's Agg canvas: off-screen, no pyplot state, the caller's backend left
alone): error rate against threshold, one line per
half-width, as ``floorscan tune`` draws them."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Dict, Optional, Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import PercentFormatter

from .._atomic import write_atomic


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
    """Writes a PNG (atomically) with one line per curve (y in [0, 1] shown in percent), a
    legend, an optional ``marker`` (x, y, text) and vertical line (x, text). ``size`` in
    pixels."""
    dpi = 100
    fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    xs = np.asarray(x, dtype=float)
    for name, ys in curves.items():
        ax.plot(xs, np.asarray(ys, dtype=float), label=name, linewidth=1.5)
    if vline is not None:
        ax.axvline(vline[0], color="0.5", linewidth=1)
        ax.annotate(
            vline[1],
            (vline[0], 1),
            xycoords=("data", "axes fraction"),
            xytext=(3, -12),
            textcoords="offset points",
            color="0.35",
        )
    if marker is not None:
        ax.plot([marker[0]], [marker[1]], "o", mfc="none", mec="k", ms=9)
        ax.annotate(marker[2], (marker[0], marker[1]), xytext=(7, 7), textcoords="offset points")
    ax.yaxis.set_major_formatter(PercentFormatter(1.0, decimals=0))
    ax.set_ylim(bottom=0)
    ax.set(title=title, xlabel=x_label, ylabel=y_label)
    ax.grid(True, color="0.9")
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return write_atomic(Path(path), buffer.getvalue())
