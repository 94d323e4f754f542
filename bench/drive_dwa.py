"""The dynamic window's step (roll-outs, costs, scores) in the Rust core against the numpy
original it replaced (tests/dynamic_window_reference.py), on the drive bench's 640 x 480
corridor frame: 160 x 160 costmap, 105 samples, the unknown-cell test on; five rounds of 200
calls each, alternating, median per round [ms].

    .venv/bin/python bench/drive_dwa.py
"""

import sys
import time

import numpy as np

sys.path.insert(0, "tests")
sys.path.insert(0, "bench")
from drive_step import corridor_frame
from dynamic_window_reference import reference_choice
from floorscan.drive import (
    AvoidanceMap,
    CostmapOptions,
    DwaOptions,
    choose_velocity,
    inflate,
    navigation_function,
)
from floorscan.pipeline.config import Config

cam, table, ranger, pose, image = corridor_frame(
    640, 480, Config().with_overrides({"ranger.kind": "edge"})
)
m = AvoidanceMap(center=pose[:2])
co, dwa = CostmapOptions(), DwaOptions()
scan = ranger.scan(image)
m.insert_visual(scan, pose, mount=cam.robot_from_camera, table=table)
cost = inflate(m.occupied(), m.cell, co)
known = m.known()
nav = navigation_function(cost, m.cell, m.origin_m, (3.95, 0.0), co, known=known)
res = {"numpy": [], "rust": []}
for _round in range(5):
    for name, f in (("numpy", reference_choice), ("rust", choose_velocity)):
        ts = []
        for _ in range(200):
            t0 = time.perf_counter()
            f(pose, (0.3, 0.0), cost, m.origin_m, m.cell, nav, (3.95, 0.0), 0.1, dwa, ~known)
            ts.append(time.perf_counter() - t0)
        res[name].append(np.median(ts) * 1e3)
print(
    {k: [round(v, 3) for v in vs] for k, vs in res.items()},
    "ratio",
    round(np.median(res["numpy"]) / np.median(res["rust"]), 2),
    "grid",
    cost.shape,
)
