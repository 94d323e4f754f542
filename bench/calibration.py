"""Calibration time for a 640x480 image (detection, fit, table) and ground-table lookup
throughput, beside what a user would do instead (evaluate the fitted model per point, or
OpenCV's pinhole + distortion model: undistortPoints and a homography).

    .venv/bin/python bench/calibration.py [--repeat 7]

Prints Markdown tables for BENCHMARKS.md. Images: the simulator's 640x480 wide-angle
calibration scenes (checkerboard, line grid) and, when ../shared/data is present, the real
Duckietown image (640x480).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import cv2
import numpy as np
from floorscan.calibration import Pattern, calibrate
from floorscan.formats.image_io import read_grey
from floorscan.sim import Camera, render_calibration

STAGES = ("detect", "fit", "table", "leave_one_out", "report")


def data_dir() -> Path:
    env = os.environ.get("FLOORSCAN_DATA")
    if env:
        return Path(env)
    here = Path(__file__).resolve().parent.parent
    for c in (here.parent / "shared" / "data", Path("/work/shared/data")):
        if c.is_dir():
            return c
    return here.parent / "shared" / "data"


def scenes():
    cam = Camera(width=640, height=480)
    for kind in ("checkerboard", "lines"):
        image, spec = render_calibration(cam, kind=kind)
        yield f"simulator {kind} (wide angle)", image, Pattern.from_toml(spec.to_toml())
    duck = data_dir() / "calibration" / "duckietown"
    if (duck / "image1.jpg").is_file():
        yield (
            "Duckietown (real, 7x5 board)",
            read_grey(duck / "image1.jpg"),
            Pattern.load(duck / "pattern.toml"),
        )


def bench_calibration(repeat: int) -> None:
    print(
        "| image | points | detect | fit | table | leave-one-out | report | total | total without leave-one-out |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, image, pattern in scenes():
        runs = []
        for _ in range(repeat):
            _table, report = calibrate(image, pattern)
            runs.append(report.timings_s)
        med = {k: statistics.median(r[k] for r in runs) for k in STAGES}
        total = sum(med.values())
        quick = total - med["leave_one_out"]
        cells = " | ".join(f"{1000 * med[k]:.0f} ms" for k in STAGES)
        print(
            f"| {name} | {report.points_found} | {cells} | **{1000 * total:.0f} ms** | {1000 * quick:.0f} ms |"
        )


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def bench_lookup(repeat: int) -> None:
    cam = Camera(width=640, height=480)
    image, spec = render_calibration(cam, kind="checkerboard")
    table, report = calibrate(image, Pattern.from_toml(spec.to_toml()), extrapolate=True)
    model = report.model
    rng = np.random.default_rng(0)
    n = 1_000_000
    u = rng.uniform(0, 639, n)
    v = rng.uniform(240, 479, n)
    # OpenCV's pinhole + distortion alternative with comparable numbers of operations: the
    # Duckietown camera's published intrinsics and a homography to the floor.
    k = np.array([[295.8, 0, 321.26], [0, 299.54, 241.74], [0, 0, 1.0]])
    dist = np.array([-0.2354, 0.0364, -0.0033, -0.0012, 0.0])
    h = np.array([[0.0, -0.2, 0.4], [-0.3, 0.0, 0.0], [0.0, 0.8, 0.45]])
    pts = np.column_stack([u, v]).reshape(-1, 1, 2)

    def opencv() -> None:
        und = cv2.undistortPoints(pts, k, dist)
        cv2.perspectiveTransform(und, h)

    rows = [
        ("floorscan GroundTable.lookup (bilinear, Rust)", lambda: table.lookup(u, v), n),
        ("fitted model evaluated per point (numpy)", lambda: model.ground(u, v), n),
        ("OpenCV undistortPoints + perspectiveTransform", opencv, n),
        (
            "floorscan GroundTable.lookup, one point per call",
            lambda: [table.lookup(float(a), float(b)) for a, b in zip(u[:20000], v[:20000])],
            20000,
        ),
    ]
    print("| lookup of image points to floor points | points | time | points/s |")
    print("|---|---:|---:|---:|")
    for name, fn, count in rows:
        t = best_of(fn, repeat)
        print(f"| {name} | {count:,} | {1000 * t:.1f} ms | {count / t / 1e6:.1f} M |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    cv2.setNumThreads(1)
    bench_calibration(args.repeat)
    print()
    bench_lookup(args.repeat)


if __name__ == "__main__":
    main()
