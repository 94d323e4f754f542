"""Per-frame cost of the floor-parallax cue (`[parallax] enabled = true`, with its memory of the
floor's edges) on a textured floor, beside what a user building a motion cue would reach for
first: OpenCV's dense optical flow between the frame and the one before (DIS at its ultrafast
preset, the quickest dense flow OpenCV has, and Farneback), one thread each.

The frames are the built-in tiled world's (10 s at 10 Hz, seed 0, the default odometry
noise), rendered at each size; the cue ranges with the exact ground table at the default
columns. Medians over the frames, milliseconds; the flow is only the flow (no decision on it).

Run: .venv/bin/python bench/parallax_cost.py [--sizes 640x480 320x240]
"""

from __future__ import annotations

import argparse
import time

import cv2
import numpy as np
from floorscan.drive.loop import make_table
from floorscan.formats.trajectory import compose
from floorscan.ranging.parallax import ParallaxRanger
from floorscan.ranging.ranger import VisualRanger
from floorscan.sim import Camera, World, simulate_run


def median_ms(samples) -> float:
    return 1e3 * float(np.median(samples))


def measure(width: int, height: int, seconds: float) -> dict:
    camera = Camera(width=width, height=height)
    run = simulate_run(World.builtin("tiles"), camera=camera, seconds=seconds, seed=0, threads=2)
    images = [np.ascontiguousarray(im) for im in run.images]
    poses = [compose(tuple(p), camera.robot_from_camera) for p in run.odometry]
    edge = VisualRanger(make_table(camera, "exact"))
    cue = ParallaxRanger(edge, memory_min_frames=2)
    dis = cv2.DISOpticalFlow_create(cv2.DISOPTICAL_FLOW_PRESET_ULTRAFAST)
    times = {"edge": [], "edge + parallax": [], "OpenCV DIS": [], "OpenCV Farneback": []}
    for k, (image, pose) in enumerate(zip(images, poses)):
        t0 = time.perf_counter()
        edge.scan(image)
        t1 = time.perf_counter()
        cue.scan(image, world_from_camera=pose)
        t2 = time.perf_counter()
        times["edge"].append(t1 - t0)
        times["edge + parallax"].append(t2 - t1)
        if k == 0:
            continue
        t0 = time.perf_counter()
        dis.calc(images[k - 1], image, None)
        t1 = time.perf_counter()
        cv2.calcOpticalFlowFarneback(images[k - 1], image, None, 0.5, 3, 15, 3, 5, 1.2, 0)
        t2 = time.perf_counter()
        times["OpenCV DIS"].append(t1 - t0)
        times["OpenCV Farneback"].append(t2 - t1)
    return {name: median_ms(v) for name, v in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", nargs="+", default=["640x480", "320x240"])
    ap.add_argument("--seconds", type=float, default=10.0)
    a = ap.parse_args()
    cv2.setNumThreads(1)
    print("| size | edge | edge + parallax | OpenCV DIS flow | OpenCV Farneback flow |")
    print("|---|---:|---:|---:|---:|")
    for size in a.sizes:
        w, h = (int(v) for v in size.split("x"))
        m = measure(w, h, a.seconds)
        p = m["edge + parallax"]
        print(
            f"| {w} x {h} | {m['edge']:.2f} ms | **{p:.1f} ms** | {m['OpenCV DIS']:.1f} ms "
            f"({p / m['OpenCV DIS']:.1f}x) | {m['OpenCV Farneback']:.1f} ms "
            f"({p / m['OpenCV Farneback']:.1f}x) |",
            flush=True,
        )


if __name__ == "__main__":
    main()
