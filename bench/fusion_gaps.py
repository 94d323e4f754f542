"""Where the fused ranger's defaults come from (`snap_fraction`, `texture_share`,
python/floorscan/ranging/fused.py): per simulated world, 20 s of its tour (seed 0, exact
table), the edge and appearance rangers at their defaults on the same columns.

- the row gap (edge row - appearance row, both boundaries, edge nearer by more than 3 rows)
  where the edge ranger is right and the appearance ranger wrong, and where the reverse;
- each frame's texture edge share (fusion::texture_edge_share: edge boundaries more than the
  snap distance below an appearance boundary, over the edge boundaries).

    .venv/bin/python bench/fusion_gaps.py [--worlds corridor room lab tiles parquet patterned]
"""

from __future__ import annotations

import argparse

import numpy as np
from floorscan.evaluation.scoring import score_columns
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import ranger_from_config
from floorscan.sim import World, simulate_run


def pct(v) -> str:
    return "-" if not len(v) else " / ".join(f"{x:.0f}" for x in np.percentile(v, [10, 50, 90]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--worlds", nargs="+", default=["corridor", "room", "lab", "tiles", "parquet", "patterned"]
    )
    a = ap.parse_args()
    print(
        "| world | gap where edge right: rows p10 / p50 / p90 (n) | gap where appearance right "
        "(n) | texture edge share per frame p10 / p50 / p90 [%] |"
    )
    print("|---|---|---|---|")
    for world in a.worlds:
        run = simulate_run(World.builtin(world), seconds=20, seed=0, labels=False, threads=1)
        table = run.camera.ground_table(spacing_px=4, max_range_m=10.0)
        fused = ranger_from_config(table, Config().with_overrides({"ranger.kind": "fused"}))
        snap = max(fused.snap_rows, fused.snap_fraction * table.image_height)
        edge_right, app_right, shares = [], [], []
        for k in range(0, len(run.images), 2):
            im = run.images[k]
            e, ap_ = fused.edge.scan(im), fused.appearance.scan(im)
            truth = (run.truth.status[k], run.truth.points[k])
            we, wa = score_columns(e, *truth).wrong, score_columns(ap_, *truth).wrong
            es, as_ = np.asarray(e.status_codes), np.asarray(ap_.status_codes)
            gap = np.asarray(e.rows) - np.asarray(ap_.rows)
            both = (es == 0) & (as_ == 0)
            sel = both & (gap > 3)
            edge_right += list(gap[sel & ~we & wa])
            app_right += list(gap[sel & we & ~wa])
            shares.append(100 * (both & (gap > snap)).sum() / max((es == 0).sum(), 1))
        print(
            f"| {world} | {pct(edge_right)} ({len(edge_right)}) | {pct(app_right)} "
            f"({len(app_right)}) | {pct(shares)} |"
        )


if __name__ == "__main__":
    main()
