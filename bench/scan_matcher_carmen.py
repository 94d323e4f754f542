"""The drive's scan matcher on real laser logs (../shared/data/carmen): the logs' corrected
(SLAM) poses are the truth; odometry is rebuilt from their increments with the simulator's
default wheel-odometry errors (1 % scale, 2 % turn scale, 1 cm / sqrt(m) wheel noise, 0.4 %
wheel difference; seeded), and the matcher corrects it scan by scan as `floorscan drive`
does. Prints the largest and median position error and the final heading error, odometry
alone against scan matching.

    .venv/bin/python bench/scan_matcher_carmen.py [--log intel] [--seeds 3] [--range 8] [--no-fusion]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
from floorscan.formats.carmen import read_carmen
from floorscan.mapping.scan_matcher import ScanMatcher, ScanMatcherOptions

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "carmen"
LOGS = {
    "intel": "intel-corrected.log.gz",
    "freiburg-079": "freiburg-079-corrected.log.gz",
    "csail": "csail-robotlaser1.log.gz",
}


def compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def between(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, math.remainder(b[2] - a[2], 2 * math.pi))


def noisy(inc, rng, wheelbase=0.3):
    """The increment as the simulator's default odometry would measure it."""
    d = math.hypot(inc[0], inc[1])
    dth = inc[2]
    left = d - 0.5 * wheelbase * dth
    right = d + 0.5 * wheelbase * dth
    left = left * (1.01 - 0.002) + 0.01 * math.sqrt(abs(left)) * rng.normal()
    right = right * (1.01 + 0.002) + 0.01 * math.sqrt(abs(right)) * rng.normal()
    d2 = 0.5 * (left + right)
    dth2 = (right - left) / (wheelbase * 1.02)
    heading = math.atan2(inc[1], inc[0]) if d > 1e-9 else 0.0
    if abs(math.remainder(heading, 2 * math.pi)) > math.pi / 2:
        d2 = -d2  # driving backwards
        heading += math.pi
    return (
        d2 * math.cos(heading - inc[2] / 2 + dth2 / 2),
        d2 * math.sin(heading - inc[2] / 2 + dth2 / 2),
        dth2,
    )


def run(scans, seed: int, range_m: float, matching: bool, fusion: bool = True):
    rng = np.random.default_rng(seed)
    truth = [tuple(s.laser_pose) for s in scans]
    matcher = ScanMatcher(
        ScanMatcherOptions(size_m=120.0, range_max_m=range_m)
        if fusion
        else ScanMatcherOptions(
            size_m=120.0, range_max_m=range_m, match_variance_scale=0.0, calibrate_odometry=False
        ),
        center=truth[0][:2],
    )
    est = truth[0]
    errors = []
    for k, s in enumerate(scans):
        if k > 0:
            est = compose(est, noisy(between(truth[k - 1], truth[k]), rng))
        r = np.asarray(s.ranges, np.float64)
        a = s.angle_min + s.angle_increment * np.arange(len(r))
        ok = np.isfinite(r) & (r > 0.05) & (r < min(range_m, (s.max_range or 80.0) - 0.5))
        pts = np.stack([r[ok] * np.cos(a[ok]), r[ok] * np.sin(a[ok])], 1)
        if matching:
            est = matcher.correct(pts, est).pose
        errors.append(math.hypot(est[0] - truth[k][0], est[1] - truth[k][1]))
    yaw = abs(math.remainder(est[2] - truth[-1][2], 2 * math.pi))
    return max(errors), float(np.median(errors)), yaw


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--log", default="intel", choices=sorted(LOGS))
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--range", type=float, default=8.0, help="laser points used [m]")
    ap.add_argument("--scans", type=int, default=0, help="first N scans (0: all)")
    ap.add_argument(
        "--no-fusion",
        action="store_true",
        help="keep each match as it is (the matcher before the filter and odometry calibration)",
    )
    a = ap.parse_args()
    path = DATA / LOGS[a.log]
    if not path.exists():
        raise SystemExit(f"{path} is absent (../shared/data/carmen)")
    scans = read_carmen(path).lasers
    if a.scans:
        scans = scans[: a.scans]
    dist = sum(
        math.hypot(q.laser_pose[0] - p.laser_pose[0], q.laser_pose[1] - p.laser_pose[1])
        for p, q in zip(scans, scans[1:])
    )
    print(f"{a.log}: {len(scans)} scans, {dist:.0f} m, points within {a.range} m")
    print("| seed | odometry: max / median error [m], final heading [rad] | scan matching |")
    print("| --- | --- | --- |")
    for seed in range(a.seeds):
        o = run(scans, seed, a.range, False)
        m = run(scans, seed, a.range, True, fusion=not a.no_fusion)
        print(
            f"| {seed} | {o[0]:.2f} / {o[1]:.2f}, {o[2]:.3f} | {m[0]:.2f} / {m[1]:.2f}, {m[2]:.3f} |"
        )


if __name__ == "__main__":
    main()
