"""The edge ranger at light levels and world x light combinations the simulated suite does not
have (held out from the choice of `noise_multiple` and `contrast`): 20 s of each world's tour,
seed 5, the camera's exact ground table; boundary error rate with a fixed threshold 10 and
`sub_pixel` (this branch's scan) and with the defaults.

    .venv/bin/python bench/edge_threshold_light.py
"""

from __future__ import annotations

import numpy as np
from floorscan import VisualRanger
from floorscan.evaluation.scenarios import Scenario, builtin_world_text, with_lighting
from floorscan.evaluation.scoring import score_columns
from floorscan.sim import World, simulate_run

cases = [
    ("corridor", 0.3, "default"),
    ("corridor", 0.7, "default"),
    ("corridor", 2.0, "default"),
    ("room", 0.45, "default"),
    ("lab", 0.45, "default"),
    ("parquet", 0.45, "default"),
    ("room", 0.3, "high"),
]
print("| world, exposure, noise | fixed T = 10, sub_pixel | defaults |")
print("|---|---:|---:|")
for world, exposure, noise in cases:
    sc = Scenario(world, noise=noise, seed=5, seconds=20.0)
    w = World.from_toml(with_lighting(builtin_world_text(world), exposure, 0.08), source_name=world)
    cam = sc.build_camera()
    run = simulate_run(
        w, camera=cam, robot=sc.build_robot(), seconds=sc.seconds, seed=sc.seed, threads=1
    )
    table = cam.ground_table(spacing_px=8)
    out = []
    for o in [dict(threshold=10, noise_multiple=0, contrast=0, refinement="sub_pixel"), {}]:
        r = VisualRanger(table, **o)
        wr = np.concatenate(
            [
                score_columns(r.scan(run.images[f]), run.truth.status[f], run.truth.points[f]).wrong
                for f in range(len(run.images))
            ]
        )
        out.append(100 * wr.mean())
    print(
        f"| {world}, exposure {exposure}, noise {noise}, seed 5 | {out[0]:.1f} % | {out[1]:.1f} % |",
        flush=True,
    )
