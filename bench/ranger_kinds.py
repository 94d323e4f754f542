"""Per-frame ranging time of each range sensor kind through the Python API, on simulated
corridor frames, at the default (placed) columns or a given count; best of `--passes` passes.

    .venv/bin/python bench/ranger_kinds.py [--passes 5] [--columns N] [--rgb]

Prints one line per resolution and kind: columns, ms per frame.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import ranger_from_config
from floorscan.sim import Camera, World, simulate_run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--columns", type=int, default=0, help="0: the default placed columns")
    ap.add_argument("--rgb", action="store_true", help="three equal channels instead of grey")
    a = ap.parse_args()
    for w, h in ((320, 240), (640, 480)):
        cam = Camera(width=w, height=h)
        run = simulate_run(
            World.builtin("corridor"), camera=cam, seconds=1, seed=0, labels=False, threads=1
        )
        images = run.images
        if a.rgb:
            images = [np.ascontiguousarray(np.stack([i, i, i], -1)) for i in images]
        table = cam.ground_table(spacing_px=4)
        for kind in ("edge", "appearance", "fused"):
            kw = {"columns": a.columns} if a.columns else {}
            r = ranger_from_config(table, Config().with_overrides({"ranger.kind": kind}), **kw)
            best = []
            for _ in range(a.passes):
                t = time.perf_counter()
                for im in images:
                    r.scan(im)
                best.append(1e3 * (time.perf_counter() - t) / len(images))
            print(f"{w}x{h} {kind}: {len(r.columns)} columns, {min(best):.3f} ms per frame")


if __name__ == "__main__":
    main()
