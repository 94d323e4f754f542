"""``floorscan eval --floors DIR``: the edge, appearance and fused rangers on real frames with
floor masks, scored in image rows per clip and per floor type, with clip-wise cross-validated
figures (options tuned on the other clips, reported on the held-out one)."""

from __future__ import annotations

from typing import Dict, Sequence

from ..pipeline.config import Config
from ..pipeline.mapper import ranger_from_config
from .floor_cv import cross_validate
from .floor_masks import (
    floor_types,
    format_floor_report,
    image_row_table,
    list_floor_frames,
    load_floor_frames,
    score_floor_frames,
    summarise_floor_scores,
)

# Cross-validation grids: the options each ranger is tuned over (values any user might try).
CV_GRIDS: Dict[str, Dict[str, Sequence[object]]] = {
    "edge": {"ranger.threshold": [5.0, 10.0, 15.0, 20.0, 30.0], "ranger.half_width_px": [2, 4, 8]},
    "appearance": {
        "appearance.min_floor_share": [0.003, 0.01, 0.03],
        "appearance.intensity_reach_bins": [1, 2],
        "appearance.min_run_px": [3, 8],
        "appearance.reference_fraction": [0.1, 0.2],
        "appearance.reference_width_fraction": [0.5, 1.0],
    },
}
CV_GRIDS["fused"] = dict(CV_GRIDS["appearance"])


FLOOR_COLUMNS = 64
"""Columns scanned per frame of a floor-mask folder (evenly spaced)."""


def floor_ranger_factory(cfg: Config, kind: str):
    """(image_width, image_height) -> a ranger of ``kind`` with ``cfg``'s options, scanning
    from the bottom row (the truth's) as far up as the image goes (no geometry), on
    ``FLOOR_COLUMNS`` evenly spaced columns unless ``cfg`` gives a count or a list (placing
    columns by floor distance needs the camera's geometry, which such frames lack)."""
    kcfg = cfg.with_overrides({"ranger.kind": kind})
    columns = cfg.ranger.columns
    if isinstance(columns, dict):
        columns = FLOOR_COLUMNS

    def make(width: int, height: int):
        return ranger_from_config(
            image_row_table(width, height),
            kcfg,
            start={"bottom_margin": 0},
            max_range_m=None,
            columns=columns,
        )

    return make


def run_floor_eval(
    folder, cfg: Config, *, kinds: Sequence[str], cv: bool, trim_mask_bottom: int = 0
) -> Dict[str, object]:
    """Scores each ranger kind at ``cfg``'s options and, with ``cv``, cross-validated. Returns
    ``{"markdown": str, "results": {kind: {...}}}``."""
    frames = list_floor_frames(folder)
    types = floor_types(folder)
    loaded = load_floor_frames(frames, trim_mask_bottom=trim_mask_bottom)
    results: Dict[str, object] = {}
    md = []
    rule = (
        "the README's rule"
        if not trim_mask_bottom
        else f"diagnostic: mask's bottom {trim_mask_bottom} rows replaced by the row above"
    )
    for kind in kinds:
        r = summarise_floor_scores(
            score_floor_frames(loaded, floor_ranger_factory(cfg, kind)), types
        )
        entry: Dict[str, object] = {"at_config": r}
        md.append(format_floor_report(r, title=f"{kind} ranger, configured options ({rule})"))
        if cv:
            grid = CV_GRIDS[kind]
            c = cross_validate(
                loaded,
                lambda opts, kind=kind: floor_ranger_factory(cfg.with_overrides(opts), kind),
                grid,
            )
            entry["cross_validated"] = c
            md.append(_format_cv(kind, c))
        results[kind] = entry
    return {"markdown": "\n".join(md), "results": results}


def _format_cv(kind: str, c: Dict[str, object]) -> str:
    lines = [
        f"### {kind}: clip-wise cross-validation (tuned on the other clips)",
        "",
        "| held-out clip | options chosen | train wrong | held-out wrong |",
        "|---|---|---:|---:|",
    ]
    for clip, h in sorted(c["held_out"].items()):
        opts = ", ".join(f"{k.split('.')[-1]}={v}" for k, v in sorted(h["options"].items()))
        lines.append(
            f"| {clip} | {opts} | {100 * h['train_error_rate']:.1f} % | {100 * h['error_rate']:.1f} % |"
        )
    lines.append(f"| **pooled held-out** | | | **{100 * c['error_rate']:.1f} %** |")
    return "\n".join(lines) + "\n"
