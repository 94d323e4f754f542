"""RGB-D truth (`floorscan.evaluation.rgbd_truth`) against a scene drawn here: a pinhole camera
0.5 m above the floor pitched 25 degrees down, a box face standing 1.5 m ahead; the depth each
pixel's ray meets first. The camera's height, every table node's ground point and the base of
the box in the floor mask are compared with the scene's geometry."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan.errors import DatasetError, FloorscanError
from floorscan.evaluation.floor_masks import floor_mask_truth
from floorscan.evaluation.rgbd_truth import fit_floor_plane, rgbd_truth
from floorscan.formats.image_io import read_grey

W, H = 320, 240
K = (250.0, 250.0, 159.5, 119.5)
HEIGHT_M, PITCH = 0.5, np.radians(25.0)
BOX_X, BOX_HALF_Y, BOX_TOP = 1.5, 0.3, 0.4
MAX_DEPTH_M = 8.0

# the camera's axes in the ground frame (x ahead, y left, z up): image right, image down, optical
RIGHT = np.array([0.0, -1.0, 0.0])
DOWN = np.array([-np.sin(PITCH), 0.0, -np.cos(PITCH)])
AHEAD = np.array([np.cos(PITCH), 0.0, -np.sin(PITCH)])


def rays(u, v):
    fx, fy, cx, cy = K
    return ((u - cx) / fx)[..., None] * RIGHT + ((v - cy) / fy)[..., None] * DOWN + AHEAD


def scene():
    """Depth [m] (0 beyond MAX_DEPTH_M) and a grey image; the ground point of every pixel."""
    u, v = np.meshgrid(np.arange(W, dtype=float), np.arange(H, dtype=float))
    d = rays(u, v)  # depth = t along these rays (unit optical component)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_floor = np.where(d[..., 2] < 0, HEIGHT_M / -d[..., 2], np.inf)
        t_box = np.where(d[..., 0] > 0, BOX_X / d[..., 0], np.inf)
    y_box, z_box = t_box * d[..., 1], HEIGHT_M + t_box * d[..., 2]
    t_box[~((np.abs(y_box) < BOX_HALF_Y) & (z_box >= 0) & (z_box <= BOX_TOP))] = np.inf
    depth = np.minimum(t_floor, t_box)
    depth[~(depth < MAX_DEPTH_M)] = 0.0
    image = np.where(t_box < t_floor, 60, 150).astype(np.uint8)
    ground = d[..., :2] * t_floor[..., None]
    return depth, image, ground


def test_height_table_and_the_boxs_base_follow_the_scene():
    depth, image, ground = scene()
    depth[200:210, 100:110] = 0.0  # a hole in the floor's depth (a dark patch)
    t = rgbd_truth(image, depth, K)
    assert t.camera_height_m == pytest.approx(HEIGHT_M, abs=1e-6)
    u0, v0 = t.crop_px
    h, w = t.floor_mask.shape
    # table nodes (every 4 px) with ground: their analytic ground points
    checked = 0
    for v in range(0, h, 8):
        for u in range(0, w, 8):
            got = t.table.lookup(float(u), float(v))
            want = ground[v + v0, u + u0]
            if got is None or not np.all(np.isfinite(want)) or np.hypot(*want) > 6:
                continue
            assert got == pytest.approx(tuple(want), abs=1e-5)
            checked += 1
    assert checked > 500
    # the last node row and column (at or past the image's edge) too: the bottom row's and the
    # right column's ground points
    for u, v in [(w - 1, h - 1), (w - 1, h // 2), (w // 2, h - 1), (w - 2, h - 3)]:
        want = ground[v + v0, u + u0]
        assert t.table.lookup(float(u), float(v)) == pytest.approx(tuple(want), abs=2e-3)
    # the box's base: where its face meets the floor, row by the camera model
    status, rows = floor_mask_truth(t.floor_mask)
    base_seen = 0
    fx, fy, cx, cy = K
    for yb in np.linspace(-0.25, 0.25, 11):
        p = np.array([BOX_X, yb, -HEIGHT_M])  # from the camera, in the ground frame
        xc, yc, zc = p @ RIGHT, p @ DOWN, p @ AHEAD
        u, v = fx * xc / zc + cx - u0, fy * yc / zc + cy - v0
        col = int(round(u))
        assert status[col] == 0
        assert rows[col] == pytest.approx(v, abs=1.5)
        base_seen += 1
    assert base_seen == 11
    # the hole in the floor's depth is floor in the mask
    assert t.floor_mask[205 - v0, 105 - u0]
    # floor nearer than the sensor sees (no depth in the bottom rows) is floor, not too close
    near = depth.copy()
    near[-12:, :120] = 0.0  # a third of the columns (the rows keep depth in the rest)
    status, _ = floor_mask_truth(rgbd_truth(image, near, K).floor_mask)
    assert not np.any(status == 2)


def test_a_plane_is_found_from_noisy_points_whatever_the_sample():
    rng = np.random.default_rng(3)
    depth, _, _ = scene()
    u, v = np.meshgrid(np.arange(W, dtype=float), np.arange(H, dtype=float))
    fx, fy, cx, cy = K
    xyz = np.stack([(u - cx) / fx, (v - cy) / fy, np.ones_like(u)], -1) * depth[..., None]
    pts = xyz[(depth > 0) & (v > H / 2)]
    pts = pts + rng.normal(0, 0.004, pts.shape)
    fits = [fit_floor_plane(pts, seed=s) for s in range(3)]
    for n, d in fits:
        assert d == pytest.approx(HEIGHT_M, abs=3e-3)
        assert np.degrees(np.arccos(min(1.0, abs(n @ fits[0][0])))) < 0.1


def test_bad_frames_are_refused_in_one_line(tmp_path):
    depth, image, _ = scene()
    with pytest.raises(DatasetError, match="registered"):
        rgbd_truth(image[:-1], depth, K)
    with pytest.raises(DatasetError, match="no depth"):
        rgbd_truth(image, np.zeros_like(depth), K)
    with pytest.raises(DatasetError, match="focal"):
        rgbd_truth(image, depth, (0.0, 250.0, 159.5, 119.5))
    wall = np.full_like(depth, 2.0)  # a wall facing the camera: no floor
    with pytest.raises(FloorscanError, match="floor plane"):
        rgbd_truth(image, wall, K)
    bad = tmp_path / "d.pgm"
    bad.write_bytes(b"P5 640 480 65535\n" + b"\0" * 10)
    with pytest.raises(FloorscanError, match="truncated"):
        read_grey(bad)  # the project's reader takes depth files: 16-bit PGM, big-endian
    ok = tmp_path / "ok.pgm"
    ok.write_bytes(b"P5 2 1 65535\n" + np.array([1000, 258], ">u2").tobytes())
    assert read_grey(ok).tolist() == [[1000, 258]]
