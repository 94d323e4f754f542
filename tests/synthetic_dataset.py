"""A small synthetic dataset for pipeline tests, independent of the simulator: a rectangular
room seen through an exact model-based ground table. A pixel shows floor when its ground point
(moved into the world by the true pose) lies inside the room, wall otherwise: exact for vertical
walls taller than the camera's view."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from floorscan import CameraMount, GroundTable, Lens
from floorscan.formats.image_io import write_png
from floorscan.formats.rig import Rig, write_rig
from floorscan.formats.trajectory import Trajectory, write_tum

W, H = 192, 144
ROOM = (-1.0, 3.0, -1.2, 1.2)  # x_min, x_max, y_min, y_max [m]


def camera_table(spacing_px: int = 4) -> GroundTable:
    lens = Lens.equidistant(f=90.0, cx=(W - 1) / 2, cy=(H - 1) / 2)
    return GroundTable.from_camera(
        lens,
        CameraMount(height_m=0.4, tilt_rad=0.5),
        image_width=W,
        image_height=H,
        spacing_px=spacing_px,
        max_range_m=6.0,
    )


def render(exact: GroundTable, pose, rng) -> np.ndarray:
    v, u = np.mgrid[0:H, 0:W].astype(np.float64)
    gx, gy = exact.lookup(u, v)
    x, y, yaw = pose
    wx = x + np.cos(yaw) * gx - np.sin(yaw) * gy
    wy = y + np.sin(yaw) * gx + np.cos(yaw) * gy
    x0, x1, y0, y1 = ROOM
    floor = np.isfinite(gx) & (wx > x0) & (wx < x1) & (wy > y0) & (wy < y1)
    img = np.where(floor, 90.0, 190.0) + rng.normal(0, 2.0, size=(H, W))
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def true_poses(n: int):
    t = 100.0 + 0.1 * np.arange(n)  # ROS times are positive
    s = t - 100.0
    return t, np.stack(
        [0.6 * np.sin(0.3 * s), 0.3 * np.sin(0.2 * s), 0.8 * np.sin(0.25 * s)], axis=1
    )


def make_dataset(folder: Path, n: int = 30, seed: int = 0) -> Path:
    folder = Path(folder)
    (folder / "images").mkdir(parents=True, exist_ok=True)
    exact = camera_table(spacing_px=1)
    rng = np.random.default_rng(seed)
    t, poses = true_poses(n)
    lines = ["# timestamp filename"]
    for i, (ti, p) in enumerate(zip(t, poses)):
        write_png(folder / "images" / f"{i:06d}.png", render(exact, p, rng))
        lines.append(f"{ti:.6f} images/{i:06d}.png")
    (folder / "images.txt").write_text("\n".join(lines) + "\n")
    # Odometry slightly longer than the images, so every frame is covered.
    tt = np.concatenate([[t[0] - 0.05], t, [t[-1] + 0.05]])
    pp = np.concatenate([poses[:1], poses, poses[-1:]])
    traj = Trajectory(tt, pp[:, 0], pp[:, 1], pp[:, 2])
    write_tum(folder / "odometry.txt", traj)
    write_tum(folder / "groundtruth.txt", traj)
    write_rig(folder / "rig.toml", Rig(x=0.0, y=0.0, yaw=0.0, height=0.4))
    return folder


def true_occupied(x: np.ndarray, y: np.ndarray, cell: float) -> np.ndarray:
    """Cells (centres x, y) that hold a wall: within half a cell of the room's boundary, or outside."""
    x0, x1, y0, y1 = ROOM
    inside = (x > x0 + cell / 2) & (x < x1 - cell / 2) & (y > y0 + cell / 2) & (y < y1 - cell / 2)
    return ~inside
