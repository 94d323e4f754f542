"""End-to-end speed and memory of `floorscan run` on simulated data.

1. Frames per second of the pipeline on a simulated 640x480 corridor run with 64 columns:
   ranging + both maps per frame with images already decoded ("decode excluded"), and the whole
   `floorscan run` loop over a dataset folder (PNG decode, CSV, bag, overlay: "decode included").
2. Peak memory of a 10-minute simulated run (6000 frames at 10 Hz, 320x240) through
   `floorscan run`'s loop: resident memory sampled every 600 frames, to show it stays flat.

Run: .venv/bin/python bench/run_pipeline.py [--minutes 10] [--fps-only] [--inline-decode]
(prints Markdown; --inline-decode decodes on the main thread, for comparison with the prefetch)
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import Mapper, run
from floorscan.pipeline.outputs import RunOutputs
from floorscan.pipeline.sources import DatasetSource
from floorscan.sim import Camera, World, simulate_run


def fps(tmp: Path) -> None:
    cfg = Config()
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
    src = DatasetSource(ds)
    m2 = Mapper(table, cfg, robot_from_camera=cam.robot_from_camera)
    t0 = time.perf_counter()
    stats = run(src, m2, RunOutputs(tmp / "out640", cfg, expected_frames=len(src)))
    incl = stats.frames_mapped / (time.perf_counter() - t0)
    t = m2.times
    print("| 640x480, 64 columns | frames/s |")
    print("|---|---:|")
    print(
        f"| decode excluded: ranging + global and local map, in memory ({n} frames) | {excl:.0f} |"
    )
    print(
        f"| decode included: whole `floorscan run` loop over the dataset folder (PNG decode, CSV, bag, overlay) | {incl:.0f} |"
    )
    print(
        f"\nper frame in the full loop: decode {1e3 * t.decode_s / n:.2f} ms, ranging {1e3 * t.ranging_s / n:.3f} ms, "
        f"mapping {1e3 * t.mapping_s / n:.3f} ms, outputs {1e3 * t.output_s / n:.2f} ms"
    )


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
    ap.add_argument(
        "--inline-decode",
        action="store_true",
        help="decode on the main thread (as before the dataset source's prefetch), to compare",
    )
    args = ap.parse_args()
    if args.inline_decode:
        DatasetSource.__iter__ = DatasetSource._frames
    with tempfile.TemporaryDirectory() as d:
        fps(Path(d))
        if not args.fps_only:
            memory(Path(d), args.minutes)
