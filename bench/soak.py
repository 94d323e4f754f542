"""Soak benchmark (issue 12): a long run of simulated 10 Hz frames through `floorscan run` with
every output on (scans CSV, ROS 2 bag, overlay GIF, local map snapshots, map, summary), its
resident memory sampled from outside once a second. Memory must stay flat.

The simulator renders one lap (`--lap-seconds`, default 60 s, 601 frames of 320x240); the soak
dataset repeats that lap's images and odometry with advancing timestamps until `--minutes` of
frames are listed (the robot starts each lap where the first began: a pose jump the map
absorbs). Decoding, ranging, mapping and every output run per frame as in a real run.

Run: .venv/bin/python bench/soak.py --minutes 60      (prints Markdown for BENCHMARKS.md)
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from floorscan.sim import Camera, World, simulate_run


def rss_mb(pid: int) -> float:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return float("nan")


def make_soak_dataset(tmp: Path, minutes: float, lap_seconds: float) -> Path:
    cam = Camera()
    sim = simulate_run(
        World.builtin("corridor"),
        camera=cam,
        seconds=lap_seconds,
        seed=7,
        threads=2,
        labels=False,
        truth=False,
    )
    lap = sim.write_dataset(tmp / "lap", calibration=None, truth=False, labels=False)
    cam.ground_table(spacing_px=8).save(tmp / "table.json")
    images = [
        line.split()
        for line in (lap / "images.txt").read_text().splitlines()
        if line.strip() and not line.startswith("#")
    ]
    odometry = [
        line.split()
        for line in (lap / "odometry.txt").read_text().splitlines()
        if line.strip() and not line.startswith("#")
    ]
    period = lap_seconds + 0.1  # one frame interval between laps
    laps = max(1, round(60.0 * minutes / period))
    soak = tmp / "soak"
    soak.mkdir()
    (soak / "images").symlink_to(lap / "images")
    if (lap / "rig.toml").exists():
        (soak / "rig.toml").write_text((lap / "rig.toml").read_text())
    with open(soak / "images.txt", "w") as f:
        f.write("# timestamp filename\n")
        for k in range(laps):
            for t, name in images:
                f.write(f"{float(t) + k * period:.6f} {name}\n")
    with open(soak / "odometry.txt", "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for k in range(laps):
            for row in odometry:
                f.write(f"{float(row[0]) + k * period:.6f} " + " ".join(row[1:]) + "\n")
    return soak


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--minutes", type=float, default=60.0, help="simulated minutes of frames")
    ap.add_argument("--lap-seconds", type=float, default=60.0)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        soak = make_soak_dataset(tmp, args.minutes, args.lap_seconds)
        frames = sum(1 for line in open(soak / "images.txt") if not line.startswith("#"))
        out = tmp / "out"
        cmd = [
            str(Path(sys.executable).with_name("floorscan")),
            "run",
            str(soak),
            "--table",
            str(tmp / "table.json"),
            "-o",
            str(out),
        ]
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        samples = []
        while proc.poll() is None:
            samples.append((time.perf_counter() - t0, rss_mb(proc.pid)))
            time.sleep(1.0)
        wall = time.perf_counter() - t0
        assert proc.returncode == 0, proc.returncode
        s = json.loads((out / "summary.json").read_text())
    by_frame = s["memory_mb"]["resident_by_frame"]
    # Flatness of the frame loop after its first 10 % (warm-up: first tiles, overlay buffer),
    # from the run's own samples (every 600 frames); the end of the run (saving the map,
    # encoding the overlay) shows in the outside samples and the peak.
    steady = [m for i, m in by_frame if i >= 0.1 * frames and m is not None]
    lo, hi, mean = min(steady), max(steady), statistics.fmean(steady)
    print(
        f"`floorscan run` on {s['counts']['frames_mapped']} of {frames} frames "
        f"({frames / 10 / 60:.0f} simulated minutes at 10 Hz, 320x240, every output on) "
        f"in {wall / 60:.1f} min ({frames / wall:.0f} frames/s)\n"
    )
    print("| elapsed | " + " | ".join(f"{p}%" for p in range(10, 101, 10)) + " |")
    print("|---|" + "---:|" * 10)
    picks = [
        samples[min(len(samples) - 1, int(len(samples) * p / 100))] for p in range(10, 101, 10)
    ]
    print("| RSS MB (sampled outside, 1 Hz) | " + " | ".join(f"{m:.0f}" for _, m in picks) + " |")
    print(
        f"\nframe loop after its first 10 % ({len(steady)} samples, one per 600 frames): "
        f"min {lo:.0f} MB, max {hi:.0f} MB, "
        f"mean {mean:.0f} MB: spread (max - min) / mean = {100 * (hi - lo) / mean:.1f} %; "
        f"peak (VmHWM) {s['memory_mb']['peak']:.0f} MB"
    )
    print(
        "\nin-process samples (frame: MB): "
        + ", ".join(f"{i}: {m:.0f}" for i, m in by_frame[:: max(1, len(by_frame) // 12)])
    )


if __name__ == "__main__":
    main()
