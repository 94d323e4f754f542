"""The range sensor on real RGB-D frames, truth from depth: the floor is the dominant plane of
the lower image (RANSAC on the back-projected depth), each pixel's ground point is its ray met
with that plane (the camera's own ground table, exact up to the plane), and the true boundary of
a column is where its floor pixels end (the floor-mask rule of `floorscan eval --real`: the
first run of 3 pixels off the plane, scanning up from the bottom). Scores each ranger kind at
the configured options, grey frames, as the issue judges them: columns wrong in status or more
than 10 cm from the true base, and in status or more than 3 rows off.

    .venv/bin/python bench/rgbd_floor_truth.py --frames DIR [--config C] [--masks-out D]

DIR holds `color_<n>.png` and `depth_<n>.pgm|png` pairs (16-bit depth, `--depth-scale` units a
metre, big-endian PGM as the Kinect tools write it) and `intrinsics.txt` (`fx fy cx cy`).
Frames are cropped to the rectangle where depth exists (a Kinect's depth sees less than its
colour camera). `--masks-out D` also writes the frames as a floor-mask folder (`images/`,
`masks/`) that `floorscan eval --real D` scores in rows.

Data used in EVALUATION.md: five real Kinect frames of a carpeted living room (NYU Depth v2
style, 640 x 480, fx 518 fy 519 cx 325.5 cy 253.5, depth in mm) redistributed in the public
repository gaoxiang12/slambook, commit 853abac7, `ch5/joinMap/color/*.png` and `depth/*.pgm`
(kept outside this repository).
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np
from floorscan.evaluation.floor_masks import floor_mask_truth
from floorscan.evaluation.real_sets import PAPER, PAPER_EDGE
from floorscan.formats.image_io import as_grey
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import RANGER_KINDS, ranger_from_config
from floorscan.ranging.ground_table import GroundTable
from PIL import Image

SPACING_PX = 4
PLANE_TOL_M = 0.02
"""A pixel is floor within this distance of the plane, plus Kinect's depth noise (0.3 % of the
squared depth in metres: 3 cm at 3 m)."""


def read_depth(path: Path) -> np.ndarray:
    data = path.read_bytes()
    if data[:2] == b"P5":
        m = re.match(rb"P5\s+(\d+)\s+(\d+)\s+(\d+)\s", data)
        w, h, top = (int(g) for g in m.groups())
        dtype = ">u2" if top > 255 else "u1"
        return np.frombuffer(data[m.end() :], dtype=dtype, count=w * h).reshape(h, w)
    return np.asarray(Image.open(path))


def fit_floor(points: np.ndarray, rng: np.random.Generator, iters: int = 400):
    """RANSAC: the plane (unit normal n, offset d: n . X + d = 0, d > 0) with the most points
    within `PLANE_TOL_M`, normal within 45 degrees of the image's up (camera -y), refined by
    least squares on its inliers."""
    best, best_count = None, -1
    for _ in range(iters):
        a, b, c = points[rng.choice(len(points), 3, replace=False)]
        n = np.cross(b - a, c - a)
        norm = np.linalg.norm(n)
        if norm < 1e-9:
            continue
        n = n / norm
        if n[1] > 0:
            n = -n
        if -n[1] < np.cos(np.radians(45)):
            continue
        d = -n @ a
        count = int(np.count_nonzero(np.abs(points @ n + d) < PLANE_TOL_M))
        if count > best_count:
            best, best_count = (n, d), count
    n, d = best
    inliers = points[np.abs(points @ n + d) < PLANE_TOL_M]
    centre = inliers.mean(0)
    _, _, vt = np.linalg.svd(inliers - centre, full_matrices=False)
    n = vt[2] if vt[2][1] < 0 else -vt[2]
    return n, -n @ centre


def frame_truth(color: np.ndarray, depth_m: np.ndarray, K, rng):
    """Crops to where depth exists; returns (image, floor mask, ground table, camera height)."""
    valid = depth_m > 0
    rows = np.nonzero(valid.mean(1) > 0.5)[0]
    cols = np.nonzero(valid.mean(0) > 0.5)[0]
    v0, v1, u0, u1 = rows[0] + 2, rows[-1] - 1, cols[0] + 2, cols[-1] - 1
    color, depth_m, valid = (a[v0:v1, u0:u1] for a in (color, depth_m, valid))
    fx, fy, cx, cy = K
    cx, cy = cx - u0, cy - v0
    h, w = depth_m.shape
    u, v = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    rays = np.stack([(u - cx) / fx, (v - cy) / fy, np.ones_like(u)], -1)
    xyz = rays * depth_m[..., None]
    lower = valid & (v > 0.5 * h)
    n, d = fit_floor(xyz[lower], rng)
    dist = np.abs(xyz @ n + d)
    on_plane = valid & (dist < PLANE_TOL_M + 0.003 * depth_m**2)
    # pixels without depth take the label of the nearest pixels with depth above and below
    # them in their column when both agree (gaps inside the floor), else not floor
    mask = on_plane.copy()
    for j in range(w):
        col_valid = np.nonzero(valid[:, j])[0]
        if col_valid.size == 0:
            continue
        missing = np.nonzero(~valid[:, j])[0]
        k = np.searchsorted(col_valid, missing)
        below_ok = k < col_valid.size
        above_ok = k > 0
        both = below_ok & above_ok
        lo = col_valid[np.clip(k - 1, 0, col_valid.size - 1)]
        hi = col_valid[np.clip(k, 0, col_valid.size - 1)]
        mask[missing[both], j] = on_plane[lo[both], j] & on_plane[hi[both], j]
    # the camera's ground frame: the foot below the camera, x along the optical axis
    # projected on the floor, y to the left (REP 103), z up (the plane's normal points to it)
    foot = -d * n
    forward = np.array([0.0, 0.0, 1.0]) - n[2] * n
    forward /= np.linalg.norm(forward)
    left = np.cross(n, forward)
    nu, nv = GroundTable.node_shape_for(image_width=w, image_height=h, spacing_px=SPACING_PX)
    un = np.minimum(np.arange(nu) * SPACING_PX, w - 1)
    vn = np.minimum(np.arange(nv) * SPACING_PX, h - 1)
    gu, gv = np.meshgrid(un.astype(float), vn.astype(float))
    r = np.stack([(gu - cx) / fx, (gv - cy) / fy, np.ones_like(gu)], -1)
    denom = r @ n
    t = np.where(denom < -1e-6, -d / np.where(denom < -1e-6, denom, -1.0), np.nan)
    p = r * t[..., None] - foot
    x, y = p @ forward, p @ left
    far = ~(np.hypot(x, y) < 20.0)
    x[far], y[far] = np.nan, np.nan
    table = GroundTable.from_arrays(x, y, image_width=w, image_height=h, spacing_px=SPACING_PX)
    return color, mask, table, float(d)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", required=True)
    ap.add_argument("--depth-scale", type=float, default=1000.0)
    ap.add_argument("--config")
    ap.add_argument("--masks-out")
    a = ap.parse_args()
    folder = Path(a.frames)
    K = [float(x) for x in (folder / "intrinsics.txt").read_text().split()[:4]]
    cfg = Config.load(a.config) if a.config else Config()
    rng = np.random.default_rng(0)
    frames = []
    for cpath in sorted(folder.glob("color_*.png")):
        stem = cpath.stem.split("_", 1)[1]
        dpath = next(folder.glob(f"depth_{stem}.*"))
        color = np.asarray(Image.open(cpath).convert("RGB"))
        depth = read_depth(dpath).astype(float) / a.depth_scale
        frames.append((stem, *frame_truth(color, depth, K, rng)))
    if a.masks_out:
        out = Path(a.masks_out)
        (out / "images").mkdir(parents=True, exist_ok=True)
        (out / "masks").mkdir(parents=True, exist_ok=True)
        for stem, color, mask, _, _ in frames:
            Image.fromarray(color).save(out / "images" / f"rgbd_f{int(stem):05d}.png")
            Image.fromarray((mask * 255).astype(np.uint8)).save(
                out / "masks" / f"rgbd_f{int(stem):05d}.png"
            )
    print(
        f"{len(frames)} frames; camera height {', '.join(f'{f[4]:.2f}' for f in frames)} m; "
        "columns wrong (status, or > 10 cm / > 3 rows from the true base)"
    )
    print("| kind | wrong at 10 cm | wrong at 3 rows | columns | truth boundary / no_boundary |")
    print("|---|---:|---:|---:|---|")
    variants = [(kind, {"ranger.kind": kind}) for kind in RANGER_KINDS]
    variants.append((PAPER, PAPER_EDGE))
    for kind, overrides in variants:
        kcfg = cfg.with_overrides(overrides)
        reach_m = kcfg.ranger.options()["max_range_m"] or np.inf
        wrong10 = wrong3 = total = tb = tn = 0
        for _, color, mask, table, _ in frames:
            ranger = ranger_from_config(table, kcfg)
            scan = ranger.scan(as_grey(color))
            cols = scan.columns.astype(np.intp)
            status, rows = floor_mask_truth(mask)
            status, rows = status[cols].astype(int), rows[cols]
            true_xy = np.array(
                [
                    table.lookup(float(c), float(r)) if s == 0 else (np.nan, np.nan)
                    for c, r, s in zip(cols, rows, status)
                ],
                dtype=float,
            ).reshape(-1, 2)
            # a true base beyond the ranger's range is open floor to it
            status[(status == 0) & ~(np.hypot(true_xy[:, 0], true_xy[:, 1]) <= reach_m)] = 1
            said = scan.status_codes.astype(int)
            same = said == status
            both = same & (status == 0)
            off_m = np.hypot(scan.x - true_xy[:, 0], scan.y - true_xy[:, 1])
            off_rows = np.abs(scan.rows - rows)
            wrong10 += int(np.count_nonzero(~same | (both & ~(off_m <= 0.10))))
            wrong3 += int(np.count_nonzero(~same | (both & ~(off_rows <= 3.0))))
            total += cols.size
            tb += int(np.count_nonzero(status == 0))
            tn += int(np.count_nonzero(status == 1))
        print(
            f"| {kind} | {100 * wrong10 / total:.1f} % | {100 * wrong3 / total:.1f} % | {total} "
            f"| {tb} / {tn} |"
        )


if __name__ == "__main__":
    main()
