"""How far a one-image calibration reaches: stranger cameras (lenses, heights, image sizes not
used while developing), one small checkerboard near the robot, the table compared with the
simulator's exact pixel -> floor mapping over every floor pixel within 3 m.

    .venv/bin/python bench/calibration_reach.py [--cameras NAME,...] [--json OUT]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import floorscan
import numpy as np
from floorscan.ranging.lens import CameraMount, Lens
from floorscan.sim import Camera
from floorscan.sim.calibration import CalibrationPattern, render_calibration


def cameras():
    """name -> (Camera, board inner corners (across, away), square [m], near row x [m])."""
    out = {}
    # The second camera: 130-degree fisheye, 640 x 480, 25 cm above the floor.
    f = 640 / 2 / math.radians(65)
    out["fisheye130_640"] = (
        Camera(
            lens=Lens.kannala_brandt(fx=f, fy=f, cx=319.5, cy=239.5, k1=0.02, k2=-0.01),
            mount=CameraMount(height_m=0.25, tilt_rad=0.35),
            width=640,
            height=480,
        ),
        (6, 8),
        0.10,
        0.36,
    )
    # The evaluation suite's barrel lens (320 x 240, 0.4 m, tilt 0.75).
    out["wide_barrel_320"] = (
        Camera(
            lens=Lens.pinhole_radial(fx=150, fy=150, cx=159.5, cy=119.5, k1=-0.28, k2=0.07),
            mount=CameraMount(height_m=0.4, tilt_rad=0.75),
        ),
        (6, 8),
        0.10,
        0.36,
    )
    # A webcam: 70 degrees, mild distortion, off-centre principal point, 0.3 m, tilted 0.45.
    out["webcam_640"] = (
        Camera(
            lens=Lens.pinhole_radial(
                fx=455, fy=452, cx=331.0, cy=228.0, k1=0.08, k2=-0.15, p1=0.001, p2=-0.0008
            ),
            mount=CameraMount(height_m=0.3, tilt_rad=0.45, roll_rad=0.02),
            width=640,
            height=480,
        ),
        (6, 8),
        0.10,
        0.40,
    )
    # Duckiebot-like: 160 degrees diagonal, strong barrel, 0.1 m high.
    out["duckie_640"] = (
        Camera(
            lens=Lens.pinhole_radial(
                fx=296, fy=300, cx=321.3, cy=241.7, k1=-0.235, k2=0.036, p1=-0.0033, p2=-0.0012
            ),
            mount=CameraMount(height_m=0.11, tilt_rad=0.3),
            width=640,
            height=480,
        ),
        (6, 5),
        0.031,
        0.17,
    )
    # The simulator's default fisheye at its default mount.
    out["default_fisheye_320"] = (Camera(), (6, 8), 0.10, 0.30)
    return out


def truth(camera, max_range_m=3.0):
    """Exact ground of every pixel centre; NaN where no floor within max_range_m."""
    v, u = np.mgrid[0 : camera.height, 0 : camera.width].astype(float)
    x, y = camera.pixel_to_ground(u, v, max_range_m=max_range_m)
    return u, v, x, y


def score(table, camera):
    u, v, tx, ty = truth(camera)
    x, y = table.lookup(u.ravel(), v.ravel())
    x, y = x.reshape(u.shape), y.reshape(u.shape)
    floor = np.isfinite(tx)
    rng = np.hypot(tx, ty)
    has = floor & np.isfinite(x)
    err = np.where(has, np.hypot(x - tx, y - ty), np.nan)
    out = {"valid_fraction_3m": float(has.sum() / max(floor.sum(), 1))}
    for lo, hi in ((0, 1), (1, 2), (2, 3)):
        ring = has & (rng >= lo) & (rng < hi)
        e = err[ring]
        out[f"max_cm_{lo}_{hi}"] = float(100 * e.max()) if e.size else float("nan")
        out[f"rms_cm_{lo}_{hi}"] = float(100 * np.sqrt(np.mean(e**2))) if e.size else float("nan")
        out[f"valid_{lo}_{hi}"] = float(
            ring.sum() / max((floor & (rng >= lo) & (rng < hi)).sum(), 1)
        )
    out["max_cm_within_2m"] = (
        float(np.nanmax(np.where(has & (rng < 2), err, np.nan)) * 100)
        if np.any(has & (rng < 2))
        else float("nan")
    )
    e = getattr(table, "error_m", None)
    if e is not None:
        pe = table.lookup_error(u.ravel(), v.ravel()).reshape(u.shape)
        ok = has & np.isfinite(pe)
        out["honest_fraction"] = float(np.mean(err[ok] <= pe[ok])) if ok.any() else float("nan")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--cameras", default="")
    ap.add_argument("--json")
    ap.add_argument("--kwargs", default="{}", help="JSON of extra calibrate() keyword options")
    ap.add_argument(
        "--intrinsics", action="store_true", help="give calibrate() the camera's true intrinsics"
    )
    ap.add_argument(
        "--views",
        type=int,
        default=1,
        help="images of the board, the robot backed up by 0.3 m between them",
    )
    a = ap.parse_args(argv)
    cams = cameras()
    names = a.cameras.split(",") if a.cameras else list(cams)
    results = {}
    for name in names:
        cam, corners, square, near_x = cams[name]
        pattern = CalibrationPattern(
            kind="checkerboard",
            near_left=(near_x, (corners[0] - 1) * square / 2),
            inner_corners=corners,
            square=square,
        )
        images, offsets = [], []
        for k in range(a.views):
            shifted = CalibrationPattern(
                kind="checkerboard",
                near_left=(near_x + 0.3 * k, pattern.near_left[1]),
                inner_corners=corners,
                square=square,
            )
            images.append(render_calibration(cam, shifted, seed=1 + k)[0])
            offsets.append(0.3 * k)
        kwargs = json.loads(a.kwargs)
        if a.intrinsics:
            kwargs["intrinsics"] = true_intrinsics(cam)
        t0 = time.perf_counter()
        try:
            table, report = floorscan.calibrate(
                images, _to_pattern(pattern), offsets_m=offsets, **kwargs
            )
        except floorscan.FloorscanError as e:
            print(f"{name}: {type(e).__name__}: {e}")
            continue
        dt = time.perf_counter() - t0
        s = score(table, cam)
        s["seconds"] = dt
        s["model"] = report.model_name
        results[name] = s
        print(
            f"{name:22s} {report.model_name:18s} valid3m {100 * s['valid_fraction_3m']:5.1f}%  "
            f"max<2m {s['max_cm_within_2m']:7.2f} cm  rms 0-1 {s['rms_cm_0_1']:6.2f} "
            f"1-2 {s['rms_cm_1_2']:6.2f} 2-3 {s['rms_cm_2_3']:7.2f} cm  max2-3 {s['max_cm_2_3']:7.1f}"
            + (f"  honest {100 * s['honest_fraction']:.0f}%" if "honest_fraction" in s else "")
            + f"  {dt:.1f}s"
        )
        sys.stdout.flush()
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=1)


def true_intrinsics(cam):
    from floorscan.calibration import Intrinsics

    lens = cam.lens
    p = lens.params
    if lens.model == "kannala_brandt":
        return Intrinsics.fisheye(
            fx=p["fx"],
            fy=p["fy"],
            cx=p["cx"],
            cy=p["cy"],
            distortion=[p["k1"], p["k2"], p["k3"], p["k4"]],
        )
    return Intrinsics.pinhole(
        fx=p["fx"],
        fy=p["fy"],
        cx=p["cx"],
        cy=p["cy"],
        distortion=[p["k1"], p["k2"], p["p1"], p["p2"], p["k3"]],
    )


def _to_pattern(p):
    from floorscan.calibration import Pattern

    return Pattern.from_toml(p.to_toml())


if __name__ == "__main__":
    main()
