"""Side-by-side map insertion speed: floorscan's OccupancyGrid against OctoMap and Bonxai, on the
same rays, in one run.

Workloads: (1) 10,000 scans of 64 rays over 360 degrees, ranges uniform in [0.2, 4] m, the
robot on a random walk in a 40 m square; (2) the real Freiburg 079 laser log (4791 scans of
360 beams; no-return readings left out). Every library inserts every scan with its
once-per-scan rule at 4 cm cells, z = 0 for OctoMap and Bonxai. Each side is timed on its
insert calls only (floorscan: one batch call per workload, GIL released; OctoMap: one
insertPointCloud per scan; Bonxai: one ProbabilisticMap::insertPointCloud per scan), best of
``--repeat`` runs. floorscan runs twice: with its default exact walk (OctoMap's cells) and with
``ray_walk="thin"`` (one cell per step along the major axis: Bonxai's cells).

Usage (from the repository root, after ``make dev``, ``make -C bench/octomap`` and
``make -C bench/bonxai BONXAI_DIR=...``; without the Bonxai binary its rows are left out):

    .venv/bin/python bench/octomap/compare.py [--scans 10000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import math
import struct
import subprocess
import sys
import tempfile
import time
from functools import partial
from pathlib import Path

import floorscan
import numpy as np
from floorscan.formats.carmen import read_carmen

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent


def synthetic(scans: int, beams: int = 64, seed: int = 1):
    """(ranges (N, B), poses (N, 3), angle_min, angle_increment, range_max)."""
    rng = np.random.default_rng(seed)
    poses = np.zeros((scans, 3))
    x = y = yaw = 0.0
    for k in range(scans):
        step, turn = 0.1 * rng.random(), 0.4 * (rng.random() - 0.5)
        x, y, yaw = x + step * math.cos(yaw), y + step * math.sin(yaw), yaw + turn
        if abs(x) > 20 or abs(y) > 20:
            x, y, yaw = min(max(x, -20), 20), min(max(y, -20), 20), yaw + math.pi
        poses[k] = (x, y, yaw)
    ranges = rng.uniform(0.2, 4.0, size=(scans, beams))
    return ranges, poses, -math.pi, 2 * math.pi / beams, 4.5


def freiburg(path: Path):
    log = read_carmen(path)
    ranges = np.stack([r.ranges for r in log.lasers])
    poses = np.array([r.laser_pose for r in log.lasers])
    r0 = log.lasers[0]
    ranges = ranges.copy()
    ranges[(ranges >= 40.0) | (ranges < 0.05)] = -np.inf  # no return / too close: left out
    return ranges, poses, r0.angle_min, r0.angle_increment, 40.0


def write_rays(path: Path, ranges, poses, angle_min, angle_increment) -> int:
    angles = angle_min + np.arange(ranges.shape[1]) * angle_increment
    rays = 0
    with open(path, "wb") as f:
        f.write(b"FSRAYS01" + struct.pack("<Q", len(poses)))
        for r, (px, py, yaw) in zip(ranges, poses):
            ok = np.isfinite(r)
            a = yaw + angles[ok]
            ends = np.column_stack([px + r[ok] * np.cos(a), py + r[ok] * np.sin(a)]).astype("<f8")
            f.write(struct.pack("<ddI", px, py, len(ends)) + ends.tobytes())
            rays += len(ends)
    return rays


def run_ours(ranges, poses, angle_min, angle_increment, range_max, ray_walk="exact"):
    grid = floorscan.OccupancyGrid(cell_size_m=0.04, ray_walk=ray_walk)
    t0 = time.perf_counter()
    stats = grid.insert_lasers(
        ranges,
        poses=poses,
        angle_min=angle_min,
        angle_increment=angle_increment,
        range_max_m=range_max,
    )
    seconds = time.perf_counter() - t0
    cells = grid.allocated_tiles * 128 * 128
    return {
        "rays": stats.rays,
        "cells_traversed": stats.cells_traversed,
        "seconds": seconds,
        "bytes_per_cell": grid._native.grid_memory_bytes / max(cells, 1),
        "memory_bytes": grid._native.grid_memory_bytes,
    }


def run_harness(command: list[str]):
    """One run of a C++ harness (octomap_insert, bonxai_insert): its JSON line."""
    return json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)


def best_of(repeat: int, runs: dict):
    """Each library's fastest of ``repeat`` runs, the libraries taking turns within a repeat
    (so a burst of load on the shared machine does not fall on one library's runs only)."""
    best: dict = {}
    for _ in range(repeat):
        for lib, run in runs.items():
            r = run()
            if lib not in best or r["seconds"] < best[lib]["seconds"]:
                best[lib] = r
    return best


def row(name, lib, r):
    rays_s = r["rays"] / r["seconds"]
    cells_s = r["cells_traversed"] / r["seconds"]
    return (
        f"| {name} | {lib} | {r['rays']:,} | {r['cells_traversed'] / r['rays']:.1f} | "
        f"{rays_s:,.0f} | "
        f"{cells_s / 1e6:,.1f} M | {1e9 / cells_s:.2f} |"
    )


def ratio(a, b) -> float:
    """a's rays/s over b's."""
    return (a["rays"] / a["seconds"]) / (b["rays"] / b["seconds"])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scans", type=int, default=10_000)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--octomap", default=str(HERE / "octomap_insert"))
    p.add_argument("--bonxai", default=str(HERE.parent / "bonxai" / "bonxai_insert"))
    p.add_argument(
        "--log",
        default=str(REPO.parent / "shared" / "data" / "carmen" / "freiburg-079-corrected.log.gz"),
    )
    args = p.parse_args(argv)
    binary = Path(args.octomap)
    if not binary.is_file():
        print(
            f"build the OctoMap side first: make -C {HERE} (needs liboctomap-dev)", file=sys.stderr
        )
        return 2
    bonxai = Path(args.bonxai)
    if not bonxai.is_file():
        print(f"(no {bonxai}: Bonxai rows left out; see bench/bonxai/Makefile)", file=sys.stderr)
    workloads = [(f"synthetic {args.scans} x 64 rays, <= 4 m", synthetic(args.scans))]
    if Path(args.log).is_file():
        workloads.append(("Freiburg 079 log (4791 x 360)", freiburg(Path(args.log))))
    else:
        print(f"(no {args.log}: real-log workload skipped)", file=sys.stderr)
    lines = [
        "| workload | library | rays | cells/ray | rays/s | cells/s | ns/cell |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for name, (ranges, poses, amin, ainc, rmax) in workloads:
            rays_file = Path(tmp) / "rays.bin"
            write_rays(rays_file, ranges, poses, amin, ainc)
            runs = {
                "octomap": partial(run_harness, [str(binary), str(rays_file), "0.04"]),
                "floorscan": partial(run_ours, ranges, poses, amin, ainc, rmax),
                # `[grid] ray_walk = "thin"`: Bonxai's and costmap_2d's cells (a Bresenham line)
                "floorscan thin": partial(run_ours, ranges, poses, amin, ainc, rmax, "thin"),
            }
            if bonxai.is_file():
                runs["bonxai"] = partial(
                    run_harness, [str(bonxai), str(rays_file), "0.04", str(rmax)]
                )
            best = best_of(args.repeat, runs)
            octo, ours, bonx = best["octomap"], best["floorscan"], best.get("bonxai")
            lines.append(row(name, "OctoMap 1.9.7", octo))
            if bonx is not None:
                lines.append(row(name, "Bonxai", bonx))
            thin = best["floorscan thin"]
            lines.append(row(name, "floorscan", ours))
            lines.append(row(name, "floorscan, thin walk", thin))
            memory = (
                f"floorscan {ours['bytes_per_cell']:.3f} B/cell, "
                f"{ours['memory_bytes'] / 1e6:.1f} MB; "
                f"OctoMap {octo['memory_bytes'] / 1e6:.1f} MB for {octo['leaf_nodes']:,} leaves"
            )
            if bonx is not None:
                memory += (
                    f"; Bonxai {bonx['memory_bytes'] / 1e6:.1f} MB for "
                    f"{bonx['active_cells']:,} cells"
                )
            lines.append(
                f"| | floorscan / OctoMap | | | **{ratio(ours, octo):.1f}x** | | ({memory}) |"
            )
            if bonx is not None:
                lines.append(f"| | floorscan / Bonxai | | | **{ratio(ours, bonx):.1f}x** | | |")
                lines.append(
                    f"| | floorscan thin walk / Bonxai | | | **{ratio(thin, bonx):.1f}x** | | |"
                )
                lines.append(f"| | Bonxai / OctoMap | | | {ratio(bonx, octo):.1f}x | | |")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
