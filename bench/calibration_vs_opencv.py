"""Calibration accuracy side by side with what a user would otherwise do: OpenCV's own camera
calibration from the same single image and the same corners (``calibrateCamera``, pinhole with
k1 k2 p1 p2 k3; ``fisheye.calibrate``, k1..k4), then each table node's ray met with the floor.
Scored against the simulator's exact image-to-ground mapping at every pixel within 3 m, inside
the calibrated region (floorscan's own table's nodes) and extrapolated (all nodes to 10 m), on
the simulator's wide-angle lens and three others.

Run: .venv/bin/python bench/calibration_vs_opencv.py  (prints a Markdown table)
"""

from __future__ import annotations

import cv2
import floorscan
import numpy as np
from floorscan import CameraMount, GroundTable, Lens
from floorscan.calibration import Pattern, calibrate
from floorscan.sim import CalibrationPattern, Camera, render_calibration

W, H, SPACING = 640, 480, 8

LENSES = [
    ("Kannala-Brandt 136 deg (simulator default)", None, None, None),
    (
        "equidistant fisheye 180 deg",
        Lens.equidistant(f=200.0, cx=322.0, cy=236.0),
        CameraMount(height_m=0.3, tilt_rad=0.7),
        (0.22, 0.40),
    ),
    (
        "plumb_bob wide-angle (Duckiebot-like)",
        Lens.pinhole_radial(
            fx=295.8, fy=299.5, cx=321.3, cy=241.7, k1=-0.2354, k2=0.0364, p1=-0.0033, p2=-0.0012
        ),
        CameraMount(height_m=0.35, tilt_rad=0.45),
        (0.30, 0.40),
    ),
    (
        "pinhole 65 deg",
        Lens.pinhole(fx=500.0, fy=500.0, cx=319.5, cy=239.5),
        CameraMount(height_m=0.6, tilt_rad=0.5),
        (0.95, 0.40),
    ),
]


def errors_cm(cam: Camera, table: GroundTable):
    v, u = np.mgrid[0:H, 0:W].astype(np.float64)
    x, y = table.lookup(u, v)
    tx, ty = cam.pixel_to_ground(u, v)
    ok = np.isfinite(x) & np.isfinite(tx) & (np.hypot(tx, ty) <= 3.0)
    e = np.hypot(x - tx, y - ty)[ok]
    if e.size == 0:
        return float("nan"), float("nan")  # no ground at all: the fit diverged
    return 100 * e.max(), 100 * np.sqrt(np.mean(e**2))


def _flag(name: str) -> int:
    """A fisheye flag: ``cv2.fisheye.X`` before OpenCV 5, ``cv2.X`` since."""
    return getattr(cv2.fisheye, name, None) or getattr(cv2, name)


def opencv_nodes(image_points, ground_points, *, fisheye: bool):
    """Ground points of the table's nodes from OpenCV's single-view calibration."""
    obj = np.c_[ground_points, np.zeros(len(ground_points))].astype(np.float64)
    img = image_points.astype(np.float64)
    k0 = np.array([[300.0, 0, (W - 1) / 2], [0, 300.0, (H - 1) / 2], [0, 0, 1]])
    if fisheye:
        flags = (
            _flag("CALIB_RECOMPUTE_EXTRINSIC")
            | _flag("CALIB_FIX_SKEW")
            | _flag("CALIB_USE_INTRINSIC_GUESS")
        )
        _, k, d, rvecs, tvecs = cv2.fisheye.calibrate(
            [obj.reshape(1, -1, 3)],
            [img.reshape(1, -1, 2)],
            (W, H),
            k0,
            np.zeros((4, 1)),
            flags=flags,
        )
    else:
        flags = cv2.CALIB_USE_INTRINSIC_GUESS | cv2.CALIB_FIX_ASPECT_RATIO
        _, k, d, rvecs, tvecs = cv2.calibrateCamera(
            [obj.astype(np.float32)], [img.astype(np.float32)], (W, H), k0, None, flags=flags
        )
    rot, _ = cv2.Rodrigues(rvecs[0])
    nu, nv = GroundTable.node_shape_for(image_width=W, image_height=H, spacing_px=SPACING)
    v, u = np.mgrid[0:nv, 0:nu].astype(np.float64) * SPACING
    px = np.stack([u.ravel(), v.ravel()], -1).reshape(-1, 1, 2)
    und = cv2.fisheye.undistortPoints(px, k, d) if fisheye else cv2.undistortPoints(px, k, d)
    rays = np.c_[und.reshape(-1, 2), np.ones(nu * nv)] @ rot
    centre = -rot.T @ np.asarray(tvecs[0]).ravel()
    depth = -centre[2] / rays[:, 2]
    hit = centre + depth[:, None] * rays
    far = ~(depth > 0) | (np.hypot(hit[:, 0], hit[:, 1]) > 10.0)
    x = np.where(far, np.nan, hit[:, 0]).reshape(nv, nu)
    y = np.where(far, np.nan, hit[:, 1]).reshape(nv, nu)
    return x, y


def table_from(x, y, keep=None) -> GroundTable:
    if keep is not None:
        x, y = np.where(keep, x, np.nan), np.where(keep, y, np.nan)
    return GroundTable.from_arrays(x, y, image_width=W, image_height=H, spacing_px=SPACING)


def main() -> None:
    print(f"floorscan {floorscan.__version__}, OpenCV {cv2.__version__}\n")
    print("| lens | method | calibrated region: max | RMS | extrapolated to 3 m: max | RMS |")
    print("|---|---|---:|---:|---:|---:|")
    for name, lens, mount, near_left in LENSES:
        cam = Camera(width=W, height=H, lens=lens, mount=mount)
        spec = (
            None
            if near_left is None
            else CalibrationPattern(kind="checkerboard", near_left=near_left)
        )
        image, spec = render_calibration(cam, spec, kind="checkerboard")
        pattern = Pattern.from_toml(spec.to_toml())
        table, report = calibrate(
            image, pattern, near_field=False, coverage="pattern", spacing_px=SPACING
        )
        extrapolated, _ = calibrate(image, pattern, coverage="all", spacing_px=SPACING)
        trusted, _ = calibrate(image, pattern, spacing_px=SPACING)
        region = np.isfinite(table.nodes[0])
        tx, ty = trusted.nodes
        rows = [
            ("floorscan.calibrate (coverage all)", table, extrapolated),
            ("floorscan.calibrate (default: trusted)", table_from(tx, ty, region), trusted),
        ]
        for method, fisheye in (
            ("OpenCV calibrateCamera", False),
            ("OpenCV fisheye.calibrate", True),
        ):
            try:
                x, y = opencv_nodes(report.image_points, report.ground_points, fisheye=fisheye)
                rows.append((method, table_from(x, y, region), table_from(x, y)))
            except cv2.error:
                rows.append((method, None, None))
        for k, (method, in_region, everywhere) in enumerate(rows):
            label = name if k == 0 else ""
            if in_region is None:
                print(f"| {label} | {method} | fails (cv2.error) | | | |")
                continue
            mx, rms = errors_cm(cam, in_region)
            emx, erms = errors_cm(cam, everywhere)
            print(f"| {label} | {method} | {mx:.2f} | {rms:.2f} | {emx:.1f} | {erms:.2f} |")


if __name__ == "__main__":
    main()
