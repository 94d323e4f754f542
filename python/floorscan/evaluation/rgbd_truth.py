"""Truth for the range sensor from an RGB-D frame: the floor is the dominant plane of the lower
image (RANSAC on the back-projected depth, refined by least squares), each pixel's ground point
is its ray met with that plane (the camera's own ground table, exact up to the plane: no
calibration pattern needed), and a pixel is floor where its depth lies on the plane. The floor
mask scores a ranger in rows as ``floorscan eval --real`` does (:mod:`.floor_masks`), the table
in metres (``bench/rgbd_floor_truth.py``).

Depth: metres, 0 where the sensor has none (a 16-bit depth PNG or PGM reads with
:func:`floorscan.formats.image_io.read_grey`, then divide by its units a metre); the colour image registered to it (one pixel, one
ray); intrinsics ``(fx, fy, cx, cy)`` of that image (pinhole, no distortion: a depth camera's
registered output).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence, Tuple

import numpy as np

from ..errors import DatasetError
from ..ranging.ground_table import GroundTable
from .floor_masks import RUN_PX

PLANE_TOLERANCE_M = 0.02
"""A pixel is floor within this distance of the plane, plus the depth's own noise
(:data:`DEPTH_NOISE_PER_M2` x depth^2: a Kinect's 3 cm at 3 m)."""

DEPTH_NOISE_PER_M2 = 0.003

MAX_FLOOR_TILT_DEG = 45.0
"""The floor's normal lies within this angle of the image's up (the camera's -y axis)."""

TABLE_SPACING_PX = 4

MAX_GROUND_RANGE_M = 20.0
"""Ground points farther than this from the camera's foot are "no ground" in the table."""


@dataclass(frozen=True)
class RgbdTruth:
    """One frame's truth: the image and its floor mask cropped to where depth exists (``crop_px``:
    the original pixel (u, v) of the cropped image's (0, 0)), the ground table of the cropped
    image, and the camera's height above the floor [m]."""

    image: np.ndarray
    floor_mask: np.ndarray
    table: GroundTable
    camera_height_m: float
    crop_px: Tuple[int, int]


def fit_floor_plane(
    points: np.ndarray, *, iterations: int = 400, seed: int = 0
) -> Tuple[np.ndarray, float]:
    """RANSAC over camera-frame points (N, 3): the plane ``n . X + d = 0`` (unit ``n`` towards
    the camera's side, ``d > 0`` the camera's height) with the most points within
    :data:`PLANE_TOLERANCE_M`, its normal within :data:`MAX_FLOOR_TILT_DEG` of the image's up,
    refined by least squares over the points within that distance of it (five rounds)."""
    points = np.asarray(points, np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) < 3:
        raise DatasetError(f"the floor plane needs (N >= 3, 3) points, got {points.shape}")
    rng = np.random.default_rng(seed)
    best, best_count = None, 0
    up = np.cos(np.radians(MAX_FLOOR_TILT_DEG))
    for _ in range(iterations):
        a, b, c = points[rng.choice(len(points), 3, replace=False)]
        n = np.cross(b - a, c - a)
        norm = np.linalg.norm(n)
        if norm < 1e-12:
            continue
        n = n / norm
        if n[1] > 0:
            n = -n
        if -n[1] < up:
            continue
        d = -n @ a
        count = int(np.count_nonzero(np.abs(points @ n + d) < PLANE_TOLERANCE_M))
        if count > best_count:
            best, best_count = (n, d), count
    if best is None or best_count < 3:
        raise DatasetError("no floor plane found in the lower image (is the floor in view?)")
    normal, offset = best
    # least squares over the plane's points, again over the new plane's (a few rounds make
    # the plane the same whichever sample RANSAC kept)
    for _ in range(5):
        inliers = points[np.abs(points @ normal + offset) < PLANE_TOLERANCE_M]
        centre = inliers.mean(0)
        normal = np.linalg.svd(inliers - centre, full_matrices=False)[2][2]
        if normal[1] > 0:
            normal = -normal
        offset = float(-normal @ centre)
    if offset <= 0:
        raise DatasetError("the floor plane found passes above the camera")
    return normal, offset


def rgbd_truth(
    image: np.ndarray, depth_m: np.ndarray, intrinsics: Sequence[float], *, seed: int = 0
) -> RgbdTruth:
    """The truth of one registered RGB-D frame (module docstring). The frame is cropped to the
    rows and columns where at least half the pixels have depth (a Kinect's depth sees less
    than its colour camera), less two pixels at each side. Pixels without depth inside take
    their column's label where the nearest pixels with depth above and below agree that it is
    floor; those below a column's last pixel with depth (nearer than the sensor sees) take that
    pixel's label."""
    depth_m = np.asarray(depth_m, np.float64)
    image = np.asarray(image)
    if depth_m.ndim != 2 or image.shape[:2] != depth_m.shape:
        raise DatasetError(
            f"image {image.shape[:2]} and depth {depth_m.shape} must be registered (same size)"
        )
    fx, fy, cx, cy = (float(v) for v in intrinsics)
    if not (fx > 0 and fy > 0):
        raise DatasetError(f"focal lengths must be > 0, got fx={fx}, fy={fy}")
    valid = np.isfinite(depth_m) & (depth_m > 0)
    rows = np.nonzero(valid.mean(1) > 0.5)[0]
    cols = np.nonzero(valid.mean(0) > 0.5)[0]
    if rows.size < 8 or cols.size < 8:
        raise DatasetError("the depth image has (almost) no depth")
    # two pixels in from the rectangle's edges, where the depth's border artifacts lie
    v0, v1, u0, u1 = rows[0] + 2, rows[-1] - 1, cols[0] + 2, cols[-1] - 1
    image, depth_m, valid = image[v0:v1, u0:u1], depth_m[v0:v1, u0:u1], valid[v0:v1, u0:u1]
    cx, cy = cx - u0, cy - v0
    h, w = depth_m.shape
    u, v = np.meshgrid(np.arange(w, dtype=np.float64), np.arange(h, dtype=np.float64))
    rays = np.stack([(u - cx) / fx, (v - cy) / fy, np.ones_like(u)], -1)
    xyz = rays * np.where(valid, depth_m, 0.0)[..., None]
    normal, offset = fit_floor_plane(xyz[valid & (v > 0.5 * h)], seed=seed)
    distance = np.abs(xyz @ normal + offset)
    on_plane = valid & (distance < PLANE_TOLERANCE_M + DEPTH_NOISE_PER_M2 * depth_m**2)
    mask = on_plane.copy()
    for j in range(w):
        have = np.nonzero(valid[:, j])[0]
        if have.size == 0:
            continue
        missing = np.nonzero(~valid[:, j])[0]
        k = np.searchsorted(have, missing)
        inside = (k > 0) & (k < have.size)
        above = have[np.clip(k - 1, 0, have.size - 1)]
        below = have[np.clip(k, 0, have.size - 1)]
        mask[missing[inside], j] = on_plane[above[inside], j] & on_plane[below[inside], j]
        # below the column's last pixel with depth (the sensor's near limit): its label
        bottom = k == have.size
        mask[missing[bottom], j] = on_plane[have[-1], j]
    _lower_bases(mask, xyz, valid, normal, offset)
    return RgbdTruth(
        image=image,
        floor_mask=mask,
        table=plane_ground_table(normal, offset, (fx, fy, cx, cy), w, h),
        camera_height_m=offset,
        crop_px=(int(u0), int(v0)),
    )


def _lower_bases(mask, xyz, valid, normal, offset) -> None:
    """Moves each column's base (its first run of :data:`~.floor_masks.RUN_PX` non-floor pixels
    from the bottom, the floor-mask rule) down to where the surface meets the floor: the lowest
    centimetres of a face lie within the plane's tolerance, but a face's pixels stand over one
    ground point while the floor's move away from the camera. Below the run, pixels above the
    floor (:data:`FACE_MIN_HEIGHT_M`) whose ground point (projected on the plane) lies within the
    depth's noise of the run's join the face."""
    h, w = mask.shape
    height = xyz @ normal + offset
    ground = xyz - height[..., None] * normal
    foot = -offset * normal
    reach = np.linalg.norm(ground - foot, axis=-1)
    for j in range(w):
        off_floor = ~mask[::-1, j]  # index k counts rows from the bottom
        runs = np.convolve(off_floor.astype(np.int64), np.ones(RUN_PX, np.int64), "valid")
        starts = np.nonzero(runs == RUN_PX)[0]
        if starts.size == 0 or starts[0] == 0:
            continue
        v = h - 1 - int(starts[0])  # the run's lowest pixel
        run = [vv for vv in range(v - RUN_PX + 1, v + 1) if valid[vv, j]]
        if not run:
            continue
        face = float(np.median(reach[run, j]))
        tol = 0.01 + DEPTH_NOISE_PER_M2 * float(np.median(xyz[run, j, 2])) ** 2
        while (
            v + 1 < h
            and valid[v + 1, j]
            and abs(reach[v + 1, j] - face) < tol
            and height[v + 1, j] > FACE_MIN_HEIGHT_M
        ):
            v += 1
            mask[v, j] = False


FACE_MIN_HEIGHT_M = 0.004
"""A face's pixel stands at least this high above the plane (the floor's own lie within the
depth's noise of it)."""


def plane_ground_table(
    normal: np.ndarray, offset: float, intrinsics: Sequence[float], width: int, height: int
) -> GroundTable:
    """The ground table of a pinhole camera above the plane ``normal . X + offset = 0``: each
    node's ray met with the plane, in the camera ground frame (REP 103: origin on the floor
    below the camera, x the optical axis projected on the floor, y to the left)."""
    fx, fy, cx, cy = (float(v) for v in intrinsics)
    n = np.asarray(normal, np.float64)
    foot = -offset * n
    forward = np.array([0.0, 0.0, 1.0]) - n[2] * n
    forward /= np.linalg.norm(forward)
    left = np.cross(n, forward)
    nu, nv = GroundTable.node_shape_for(
        image_width=width, image_height=height, spacing_px=TABLE_SPACING_PX
    )
    # nodes at k x spacing, the last ones at or past the image's edge (the table's layout)
    un = (np.arange(nu) * TABLE_SPACING_PX).astype(np.float64)
    vn = (np.arange(nv) * TABLE_SPACING_PX).astype(np.float64)
    gu, gv = np.meshgrid(un, vn)
    r = np.stack([(gu - cx) / fx, (gv - cy) / fy, np.ones_like(gu)], -1)
    down = r @ n
    t = np.full(down.shape, np.nan)
    hits = down < -1e-9
    t[hits] = -offset / down[hits]
    p = r * t[..., None] - foot
    x, y = p @ forward, p @ left
    far = ~(np.hypot(x, y) < MAX_GROUND_RANGE_M)
    x[far], y[far] = np.nan, np.nan
    return GroundTable.from_arrays(
        x, y, image_width=width, image_height=height, spacing_px=TABLE_SPACING_PX
    )
