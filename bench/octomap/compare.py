"""Side-by-side map insertion speed: floorscan's OccupancyGrid against OctoMap, on the same rays.

Workloads: (1) 10,000 scans of 64 rays over 360 degrees, ranges uniform in [0.2, 4] m, the
robot on a random walk in a 40 m square; (2) the real Freiburg 079 laser log (4791 scans of
360 beams; no-return readings left out). Both libraries insert every scan with their
once-per-scan rule at 4 cm cells, z = 0 for OctoMap. Each side is timed on its insert calls
only (floorscan: one batch call per workload, GIL released; OctoMap: one insertPointCloud per
scan), best of ``--repeat`` runs.

Usage (from the repository root, after ``make dev`` and ``make -C bench/octomap``):

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


def run_ours(ranges, poses, angle_min, angle_increment, range_max, repeat: int):
    best = None
    for _ in range(repeat):
        grid = floorscan.OccupancyGrid(cell_size_m=0.04)
        t0 = time.perf_counter()
        stats = grid.insert_lasers(
            ranges,
            poses=poses,
            angle_min=angle_min,
            angle_increment=angle_increment,
            range_max_m=range_max,
        )
        seconds = time.perf_counter() - t0
        if best is None or seconds < best["seconds"]:
            cells = grid.allocated_tiles * 128 * 128
            best = {
                "rays": stats.rays,
                "cells_traversed": stats.cells_traversed,
                "seconds": seconds,
                "bytes_per_cell": grid._native.grid_memory_bytes / max(cells, 1),
                "memory_bytes": grid._native.grid_memory_bytes,
            }
    return best


def run_octomap(binary: Path, rays_file: Path, repeat: int):
    best = None
    for _ in range(repeat):
        out = subprocess.run(
            [str(binary), str(rays_file), "0.04"], check=True, capture_output=True, text=True
        ).stdout
        r = json.loads(out)
        if best is None or r["seconds"] < best["seconds"]:
            best = r
    return best


def row(name, lib, r):
    rays_s = r["rays"] / r["seconds"]
    cells_s = r["cells_traversed"] / r["seconds"]
    return (
        f"| {name} | {lib} | {r['rays']:,} | {r['cells_traversed'] / r['rays']:.1f} | "
        f"{rays_s:,.0f} | "
        f"{cells_s / 1e6:,.1f} M | {1e9 / cells_s:.2f} |"
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scans", type=int, default=10_000)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--octomap", default=str(HERE / "octomap_insert"))
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
            octo = run_octomap(binary, rays_file, args.repeat)
            ours = run_ours(ranges, poses, amin, ainc, rmax, args.repeat)
            lines.append(row(name, "OctoMap 1.9.7", octo))
            lines.append(row(name, "floorscan", ours))
            speedup = (ours["rays"] / ours["seconds"]) / (octo["rays"] / octo["seconds"])
            lines.append(
                f"| | speed-up | | | **{speedup:.0f}x** | | "
                f"(floorscan {ours['bytes_per_cell']:.3f} B/cell, "
                f"{ours['memory_bytes'] / 1e6:.1f} MB; "
                f"OctoMap {octo['memory_bytes'] / 1e6:.1f} MB for {octo['leaf_nodes']:,} leaves) |"
            )
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
