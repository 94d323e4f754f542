"""Clip-wise cross-validation of a ranger's options on floor-mask frames, so a figure measured
on a development set says how the method does on clips it was not tuned on: for each clip, the
grid point with the fewest wrong columns over the other clips is chosen and scored on the
held-out clip; the held-out figures are pooled over all clips."""

from __future__ import annotations

import itertools
from typing import Callable, Dict, List, Sequence

from .floor_masks import LoadedFrame, score_floor_frames

# (options dict) -> ranger factory (image_width, image_height) -> ranger
FactoryOfOptions = Callable[[Dict[str, object]], Callable[[int, int], object]]


def option_grid(grid: Dict[str, Sequence[object]]) -> List[Dict[str, object]]:
    """Every combination of the grid's values."""
    keys = sorted(grid)
    return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]


def cross_validate(
    loaded: Sequence[LoadedFrame], factory: FactoryOfOptions, grid: Dict[str, Sequence[object]]
) -> Dict[str, object]:
    """Leave-one-clip-out. Returns ``{"held_out": {clip: {"options", "wrong", "columns",
    "error_rate"}}, "error_rate": pooled held-out share of wrong columns}``."""
    points = option_grid(grid)
    scores = [score_floor_frames(loaded, factory(p)) for p in points]
    clips = sorted(scores[0]) if scores else []
    held_out: Dict[str, Dict[str, object]] = {}

    def train_error(s, held: str) -> float:
        w = sum(v[0] for c, v in s.items() if c != held)
        n = sum(v[1] for c, v in s.items() if c != held)
        return w / n if n else 0.0

    for clip in clips:
        best = min(range(len(points)), key=lambda i: train_error(scores[i], clip))
        wrong, n = scores[best][clip][0], scores[best][clip][1]
        held_out[clip] = {
            "options": points[best],
            "train_error_rate": train_error(scores[best], clip),
            "wrong": wrong,
            "columns": n,
            "error_rate": wrong / n if n else float("nan"),
        }
    total_w = sum(h["wrong"] for h in held_out.values())
    total_n = sum(h["columns"] for h in held_out.values())
    return {"held_out": held_out, "error_rate": total_w / total_n if total_n else float("nan")}
