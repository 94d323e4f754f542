"""Real laser logs mapped from their raw odometry (`floorscan map-log --poses odometry`) against
the map at the poses the log's SLAM run wrote: the share of the cells that map knows (free or
occupied) classified alike, and occupied precision / recall within one cell, for dead reckoning
(`[slam] mode = "off"`), local scan matching (`"local"`, the camera runs' default) and loop
closure over a pose graph (`"graph"`, map-log's default; needs GTSAM).

    .venv/bin/python bench/laser_odometry.py ../shared/data/carmen/intel-corrected.log.gz
"""

from __future__ import annotations

import argparse
import math
import time

import cv2
import numpy as np
from floorscan import OccupancyGrid
from floorscan.commands.map_log import map_lasers
from floorscan.formats.carmen import read_carmen
from floorscan.pipeline.config import Config
from floorscan.pipeline.laser_odometry import lasers_at_odometry
from floorscan.pipeline.mapper import grid_kwargs

MAX_RANGE_M, MIN_RANGE_M = 40.0, 0.05  # map-log's defaults


def build(cfg: Config, lasers) -> OccupancyGrid:
    grid = OccupancyGrid(**grid_kwargs(cfg))
    map_lasers(grid, lasers, max_range_m=MAX_RANGE_M, min_range_m=MIN_RANGE_M)
    return grid


def compare(grid: OccupancyGrid, reference: OccupancyGrid):
    rc = reference.occupancy_classes()
    c = grid.occupancy_classes(extent=reference.extent)
    known = rc != 1
    agree = float((c[known] == rc[known]).mean())
    occ, rocc = c == 2, rc == 2
    kernel = np.ones((3, 3), np.uint8)
    near_ref = cv2.dilate(rocc.astype(np.uint8), kernel) > 0
    near_occ = cv2.dilate(occ.astype(np.uint8), kernel) > 0
    precision = float((occ & near_ref).sum() / max(occ.sum(), 1))
    recall = float((rocc & near_occ).sum() / max(rocc.sum(), 1))
    return agree, precision, recall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("logs", nargs="+")
    a = ap.parse_args()
    cfg = Config()
    for path in a.logs:
        log = read_carmen(path)
        reference = build(cfg, log.lasers)
        truth = np.array([r.laser_pose for r in log.lasers])
        for name, c in (
            ("dead reckoning", cfg.with_overrides({"slam.mode": "off"})),
            ("local matching", cfg.with_overrides({"slam.mode": "local"})),
            ("pose graph", cfg.with_overrides({"slam.mode": "graph"})),
        ):
            t0 = time.perf_counter()
            lasers, summary = lasers_at_odometry(
                log, c, range_max_m=MAX_RANGE_M, range_min_m=MIN_RANGE_M
            )
            seconds = time.perf_counter() - t0
            end = np.array(lasers[-1].laser_pose) - truth[-1]
            agree, precision, recall = compare(build(cfg, lasers), reference)
            loops = (
                f", {summary['loop_closures']} loop closures" if "loop_closures" in summary else ""
            )
            print(
                f"{path}: {name}{loops}: agreement {100 * agree:.1f} %, occupied precision "
                f"{100 * precision:.1f} % / recall {100 * recall:.1f} %; final pose "
                f"{math.hypot(end[0], end[1]):.2f} m / "
                f"{math.degrees(math.remainder(end[2], 2 * math.pi)):.1f} deg off; "
                f"{1000 * seconds / len(lasers):.2f} ms per scan",
                flush=True,
            )


if __name__ == "__main__":
    main()
