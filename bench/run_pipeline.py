"""End-to-end speed and memory of `floorscan run` on simulated data.

1. Frames per second of the pipeline on a simulated 640x480 corridor run with 64 columns:
   ranging + both maps per frame with images already decoded ("decode excluded"), and the whole
   `floorscan run` loop over a dataset folder (PNG decode, scans CSV, ROS 2 bag, overlay GIF,
   local snapshots, map: "decode included"), side by side with the baseline a careful user
   writes (OpenCV's `cv2.imread` on a 2-thread pool feeding the same mapper and outputs) and
   with decoding inline; the variants alternate, `--repeats` runs each.
2. Peak memory of a 10-minute simulated run (6000 frames at 10 Hz, 320x240) through
   `floorscan run`'s loop: resident memory sampled every 600 frames, to show it stays flat.

Run: .venv/bin/python bench/run_pipeline.py [--minutes 10] [--fps-only] [--repeats 3]
[--ranger edge|appearance|fused] [--columns N] (prints Markdown). BENCHMARKS.md gives the edge
ranger on 64 columns (the bench's defaults) and the fused ranger on columns placed by floor
distance (`--ranger fused --columns 0`).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import Mapper, run
from floorscan.pipeline.outputs import RunOutputs
from floorscan.pipeline.sources import DatasetSource, Frame
from floorscan.sim import Camera, World, simulate_run


class OpenCVPoolSource(DatasetSource):
    """The baseline a careful user writes around floorscan's library: ``cv2.imread`` (GIL
    released) on a pool of two threads, four frames ahead, feeding the same mapper and the same
    outputs."""

    def __iter__(self):
        import cv2

        with ThreadPoolExecutor(max_workers=2) as pool:
            todo = iter(enumerate(self.entries))
            ahead: deque = deque()

            def submit() -> None:
                nxt = next(todo, None)
                if nxt is not None:
                    ahead.append((nxt, pool.submit(cv2.imread, str(nxt[1].path), -1)))

            for _ in range(4):
                submit()
            while ahead:
                (i, e), future = ahead.popleft()
                submit()
                img = future.result()
                yield Frame(i, e.timestamp, img, None if img is not None else "unreadable")


class InlineSource(DatasetSource):
    """Each frame decoded in its turn on the frame loop's thread (read_grey: the Rust decoder)."""

    __iter__ = DatasetSource._frames


SOURCES = {
    "floorscan run (Rust PNG read-ahead threads)": DatasetSource,
    "baseline: cv2.imread on a 2-thread pool, 4 frames ahead": OpenCVPoolSource,
    "Rust PNG decoding inline, no read-ahead": InlineSource,
}


def fps(tmp: Path, repeats: int, cfg: Config) -> None:
    cam = Camera(width=640, height=480)
    sim = simulate_run(
        World.builtin("corridor"),
        camera=cam,
        seconds=30.0,
        seed=3,
        threads=2,
        labels=False,
        truth=False,
    )
    table = cam.ground_table(spacing_px=8)
    mapper = Mapper(table, cfg, robot_from_camera=cam.robot_from_camera)
    n = len(sim)
    for k in range(min(n, 20)):  # warm up
        mapper.process(
            sim.images[k], timestamp=float(sim.timestamps[k]), pose=tuple(sim.odometry[k])
        )
    mapper = Mapper(table, cfg, robot_from_camera=cam.robot_from_camera)
    t0 = time.perf_counter()
    for k in range(n):
        mapper.process(
            sim.images[k], timestamp=float(sim.timestamps[k]), pose=tuple(sim.odometry[k])
        )
    excl = n / (time.perf_counter() - t0)
    ds = sim.write_dataset(tmp / "ds640", calibration=None, truth=False, labels=False)
    results: dict = {name: [] for name in SOURCES}
    cpu_ms: dict = {name: [] for name in SOURCES}
    per_frame: dict = {}
    for rep in range(repeats):  # alternating, so load changes hit every variant alike
        for name, source in SOURCES.items():
            src = source(ds)
            m2 = Mapper(table, cfg, robot_from_camera=cam.robot_from_camera)
            out = RunOutputs(tmp / f"out{rep}-{source.__name__}", cfg, expected_frames=len(src))
            c0, t0 = time.process_time(), time.perf_counter()
            stats = run(src, m2, out, strict=True)
            results[name].append(stats.frames_mapped / (time.perf_counter() - t0))
            cpu_ms[name].append(1e3 * (time.process_time() - c0) / stats.frames_mapped)
            t = m2.times
            per_frame[name] = (
                f"waiting for frames {1e3 * t.decode_s / n:.2f} ms, ranging "
                f"{1e3 * t.ranging_s / n:.3f} ms, mapping {1e3 * t.mapping_s / n:.3f} ms, outputs "
                f"{1e3 * t.output_s / n:.2f} ms"
            )
    best = {name: max(v) for name, v in results.items()}
    base = best["baseline: cv2.imread on a 2-thread pool, 4 frames ahead"]
    print(
        f"| 640x480, {cfg.ranger.kind} ranger, {len(mapper.ranger.columns)} columns, {n} frames "
        "| frames/s (each run) | best | vs baseline "
        "| CPU ms per frame, all threads (least) |"
    )
    print("|---|---:|---:|---:|---:|")
    print(
        f"| decode excluded: ranging + global and local map, images in memory | {excl:.0f} | | | |"
    )
    for name, v in results.items():
        runs = " / ".join(f"{x:.0f}" for x in v)
        print(
            f"| {name}, every output on | {runs} | {best[name]:.0f} | {best[name] / base:.2f}x "
            f"| {min(cpu_ms[name]):.2f} |"
        )
    print("\nper frame on the frame loop's thread (last run of each):")
    for name, text in per_frame.items():
        print(f"- {name}: {text}")


def memory(tmp: Path, minutes: float) -> None:
    """`floorscan run` in its own process on a long simulated dataset; its summary.json holds
    resident memory every 600 frames and the process's peak."""
    import json
    import subprocess
    import sys

    cam = Camera()
    sim = simulate_run(
        World.builtin("corridor"),
        camera=cam,
        seconds=60.0 * minutes,
        seed=4,
        threads=2,
        labels=False,
        truth=False,
    )
    ds = sim.write_dataset(tmp / "ds_long", calibration=None, truth=False, labels=False)
    del sim
    cam.ground_table(spacing_px=8).save(tmp / "table.json")
    out = tmp / "out_long"
    cmd = [
        sys.executable,
        "-m",
        "floorscan",
        "run",
        str(ds),
        "--table",
        str(tmp / "table.json"),
        "-o",
        str(out),
    ]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    s = json.loads((out / "summary.json").read_text())
    samples = s["memory_mb"]["resident_by_frame"]
    print(
        f"\n`floorscan run` on {s['counts']['frames_mapped']} frames ({minutes:g} simulated minutes, 320x240, all outputs on): resident memory [MB] by frame\n"
    )
    print("| frame | " + " | ".join(str(i) for i, _ in samples) + " |")
    print("|---|" + "---:|" * len(samples))
    print("| RSS MB | " + " | ".join(f"{m:.0f}" for _, m in samples) + " |")
    print(f"\npeak resident memory of the `floorscan run` process: {s['memory_mb']['peak']:.0f} MB")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--fps-only", action="store_true", help="skip the memory run")
    ap.add_argument("--repeats", type=int, default=3, help="alternating runs of each variant")
    ap.add_argument("--ranger", default="edge", choices=["edge", "appearance", "fused"])
    ap.add_argument("--columns", type=int, default=64, help="0: the configuration's default")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        over = {"ranger.kind": args.ranger}
        if args.columns:
            over["ranger.columns"] = args.columns
        fps(Path(d), args.repeats, Config().with_overrides(over))
        if not args.fps_only:
            memory(Path(d), args.minutes)
