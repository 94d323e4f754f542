"""Recordings for the fleet and evidence tests: the synthetic room of synthetic_dataset.py
driven along its wavy path from different start poses (true poses as odometry)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from floorscan.formats.image_io import write_png
from floorscan.formats.rig import Rig, write_rig
from floorscan.formats.trajectory import Trajectory, write_tum
from synthetic_dataset import camera_table, render, true_poses


def make_recording(folder: Path, *, n: int = 20, seed: int = 0, start=(0.0, 0.0, 0.0)) -> Path:
    """A dataset folder whose poses are synthetic_dataset's path moved to start at ``start``."""
    folder = Path(folder)
    (folder / "images").mkdir(parents=True, exist_ok=True)
    exact = camera_table(spacing_px=1)
    rng = np.random.default_rng(seed)
    t, poses = true_poses(n)
    poses = poses - poses[0] + np.asarray(start, dtype=float)
    lines = ["# timestamp filename"]
    for i, (ti, p) in enumerate(zip(t, poses)):
        write_png(folder / "images" / f"{i:06d}.png", render(exact, p, rng))
        lines.append(f"{ti:.6f} images/{i:06d}.png")
    (folder / "images.txt").write_text("\n".join(lines) + "\n")
    tt = np.concatenate([[t[0] - 0.05], t, [t[-1] + 0.05]])
    pp = np.concatenate([poses[:1], poses, poses[-1:]])
    traj = Trajectory(tt, pp[:, 0], pp[:, 1], pp[:, 2])
    write_tum(folder / "odometry.txt", traj)
    write_rig(folder / "rig.toml", Rig(x=0.0, y=0.0, yaw=0.0, height=0.4))
    return folder


def sum_by_hand(maps) -> tuple:
    """(origin, values): evidence arrays summed with plain numpy on the union of their extents
    (an independent reference for the merge)."""
    s = maps[0].cell_size_m
    o0 = np.asarray(maps[0].origin_m)
    offs = [np.rint((np.asarray(m.origin_m) - o0) / s).astype(int) for m in maps]
    lo = np.min(offs, axis=0)
    hi = np.max([o + m.values.shape[::-1] for o, m in zip(offs, maps)], axis=0)
    total = np.zeros((hi[1] - lo[1], hi[0] - lo[0]), dtype=np.int64)
    for o, m in zip(offs, maps):
        x, y = o - lo
        h, w = m.values.shape
        total[y : y + h, x : x + w] += m.values
    return tuple(o0 + s * lo), total
