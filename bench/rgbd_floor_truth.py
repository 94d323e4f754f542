"""The range sensor on real RGB-D frames, truth from depth: the floor is the dominant plane of
the lower image (RANSAC on the back-projected depth), each pixel's ground point is its ray met
with that plane (the camera's own ground table, exact up to the plane), and the true boundary of
a column is where its floor pixels end (the floor-mask rule of `floorscan eval --real`: the
first run of 3 pixels off the plane, scanning up from the bottom). Scores each ranger kind at
the configured options, grey frames (`floorscan.evaluation.rgbd_truth`), as the issue judges them: columns wrong in status or more
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
from pathlib import Path

import numpy as np
from floorscan.evaluation.floor_masks import floor_mask_truth
from floorscan.evaluation.real_sets import PAPER, PAPER_EDGE
from floorscan.evaluation.rgbd_truth import rgbd_truth
from floorscan.formats.image_io import as_grey, read_grey
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import RANGER_KINDS, ranger_from_config
from PIL import Image


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
    frames = []
    for cpath in sorted(folder.glob("color_*.png")):
        stem = cpath.stem.split("_", 1)[1]
        dpath = next(folder.glob(f"depth_{stem}.*"), None)
        if dpath is None:
            raise SystemExit(f"{cpath}: no depth_{stem}.pgm or .png beside it")
        color = np.asarray(Image.open(cpath).convert("RGB"))
        depth = read_grey(dpath).astype(float) / a.depth_scale
        t = rgbd_truth(color, depth, K)
        frames.append((stem, t.image, t.floor_mask, t.table, t.camera_height_m))
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
