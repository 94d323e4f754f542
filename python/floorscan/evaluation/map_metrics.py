"""Map metrics beyond :func:`floorscan.evaluation.scoring.score_map`: how much of the free space along the
path the map knows, and how many frames of a new view the local map needs to be reliable."""

from __future__ import annotations

from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..mapping.local_map import LocalMap
from ..mapping.log_odds import Occupancy
from ..ranging.scan import ColumnStatus
from .case import TruthRaster
from .scoring import sample_truth

RELIABLE_AGREEMENT = 0.95
"""Agreement of the local map with the truth over a view above which the map is reliable."""


def classes_at(grid, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The grid's classes (0 free, 1 unknown, 2 occupied) at world points; 1 outside."""
    ext = grid.extent
    classes = grid.occupancy_classes()
    i = np.floor((x - ext.origin_m[0]) / ext.cell_size_m).astype(np.int64)
    j = np.floor((y - ext.origin_m[1]) / ext.cell_size_m).astype(np.int64)
    inside = (i >= 0) & (i < ext.width) & (j >= 0) & (j < ext.height)
    out = np.ones(x.shape, np.uint8)
    out[inside] = classes[j[inside], i[inside]]
    return out


def agreement_at(grid, x: np.ndarray, y: np.ndarray, truth: np.ndarray) -> float:
    """Share of points (truth known) where the grid's class is the truth's; unknown cells of
    the grid count as disagreeing."""
    c = classes_at(grid, x, y)
    ok = ((c == Occupancy.OCCUPIED) & (truth == 100)) | ((c == Occupancy.FREE) & (truth == 0))
    return float(ok.mean()) if ok.size else float("nan")


def free_known_share(
    grid, raster: TruthRaster, path_xy: np.ndarray, *, radius_m: float = 1.0
) -> float:
    """Share of the truly free cells within ``radius_m`` of the path (true robot positions,
    (K, 2) [m]) that the map classifies free."""
    import cv2

    h, w = raster.cells.shape
    res = raster.resolution_m
    mask = np.zeros((h, w), np.uint8)
    r_px = max(1, int(round(radius_m / res)))
    for x, y in path_xy[:: max(1, len(path_xy) // 400)]:
        i = int((x - raster.origin[0]) / res)
        j = int((y - raster.origin[1]) / res)
        cv2.circle(mask, (i, j), r_px, 1, thickness=-1)
    sel = (mask > 0) & (raster.cells == 0)
    if not sel.any():
        return float("nan")
    jj, ii = np.nonzero(sel)
    cx = raster.origin[0] + (ii + 0.5) * res
    cy = raster.origin[1] + (jj + 0.5) * res
    return float((classes_at(grid, cx, cy) == Occupancy.FREE).mean())


def compose(a: Sequence[float], b: Sequence[float]) -> Tuple[float, float, float]:
    """a * b for planar poses (x, y, yaw)."""
    c, s = np.cos(a[2]), np.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def covered_range_m(table, columns: np.ndarray, *, row_step_px: float = 2.0) -> np.ndarray:
    """Per image column: the farthest ground range [m] the table gives going up the column
    from its bottom row until the first row without ground (0 where the bottom has none)."""
    h = table.image_height
    rows = np.arange(h - 1.0, -1.0, -row_step_px)
    u = np.repeat(np.asarray(columns, np.float64)[:, None], rows.size, 1)
    x, y = table.lookup(u, np.broadcast_to(rows, u.shape))
    r = np.hypot(x, y)
    ground = np.isfinite(r)
    # rows up to the first one without ground, from the bottom
    run = np.cumprod(ground, axis=1).astype(bool)
    return np.where(run, r, 0.0).max(axis=1, initial=0.0)


def view_cells(
    true_status: np.ndarray,
    true_points: np.ndarray,
    world_from_camera: Sequence[float],
    *,
    table,
    cell_size_m: float,
    max_range_m: float,
    window: Optional[Tuple[Tuple[float, float], Tuple[float, float]]] = None,
) -> Tuple[np.ndarray, np.ndarray]:
    """Centres (x, y) [m, world] of the map cells one frame views: along every column with a
    true boundary, the floor from the lowest visible ground point to the boundary (or the range
    limit, or the farthest floor the ground table covers in that column: the sensor sees no
    farther), and the boundary's own cell when within them. ``window`` ((x0, y0), (x1, y1))
    keeps only cells inside it."""
    h = table.image_height
    boundary = np.nonzero(true_status == ColumnStatus.BOUNDARY)[0]
    if boundary.size == 0:
        return np.zeros(0), np.zeros(0)
    near_x, near_y = table.lookup(boundary.astype(np.float64), np.full(boundary.size, h - 3.0))
    covered = covered_range_m(table, boundary)
    xs: List[np.ndarray] = []
    ys: List[np.ndarray] = []
    step = cell_size_m / 2
    for k, u in enumerate(boundary):
        px, py = true_points[u]
        r = float(np.hypot(px, py))
        r0 = float(np.hypot(near_x[k], near_y[k]))
        if not np.isfinite(r) or not np.isfinite(r0) or r <= r0:
            continue
        reach = min(max_range_m, covered[k])
        end = min(r, reach)
        t = np.arange(r0, end + 1e-9, step)
        if r <= reach:
            t = np.append(t, r + step / 2)  # just behind the base: the obstacle's cell
        xs.append(px * t / r)
        ys.append(py * t / r)
    if not xs:
        return np.zeros(0), np.zeros(0)
    gx, gy = np.concatenate(xs), np.concatenate(ys)
    ox, oy, oyaw = world_from_camera
    c, s = np.cos(oyaw), np.sin(oyaw)
    wx, wy = ox + c * gx - s * gy, oy + s * gx + c * gy
    cells = np.unique(
        np.stack([np.floor(wx / cell_size_m), np.floor(wy / cell_size_m)], axis=1).astype(np.int64),
        axis=0,
    )
    cx = (cells[:, 0] + 0.5) * cell_size_m
    cy = (cells[:, 1] + 0.5) * cell_size_m
    if window is not None:
        (x0, y0), (x1, y1) = window
        keep = (cx >= x0) & (cx < x1) & (cy >= y0) & (cy < y1)
        cx, cy = cx[keep], cy[keep]
    return cx, cy


def frames_to_reliable(
    scans: Sequence,
    case,
    grid_kwargs: Dict[str, object],
    *,
    local_size_m: float,
    max_range_m: float,
    starts: Sequence[int],
    max_frames: int = 10,
    local_map: str = "octomap",
) -> List[Optional[int]]:
    """For each start frame k0 (a new view: a fresh local map), the number of frames k0, k0+1,
    ... inserted (with true poses) after which the local map agrees with the truth on more than
    :data:`RELIABLE_AGREEMENT` of the cells frame k0 views inside the window; None when
    ``max_frames`` do not suffice or the view has no truth.

    ``local_map``: ``"octomap"``, the robot-fixed :class:`~floorscan.mapping.LocalMap` of
    ``floorscan run`` (OctoMap's update rule: constant evidence per reading, ``grid_kwargs``'
    ``visual`` or the local map's default); or ``"avoidance"``, the drive's
    :class:`~floorscan.drive.AvoidanceMap` (its default options, no decay, ``local_size_m``
    wide) fed with the calibrated inverse sensor model (``VisualSensorModel``, the table's
    error bars), scored on its own cells."""
    if local_map not in ("octomap", "avoidance"):
        raise ValueError(f"local_map must be 'octomap' or 'avoidance', got {local_map!r}")
    raster = case.raster
    out: List[Optional[int]] = []
    mount = tuple(case.robot_from_camera)
    if local_map == "avoidance":
        from ..drive.avoidance_map import AvoidanceMap, AvoidanceMapOptions

        options = AvoidanceMapOptions(size_m=local_size_m, half_life_s=None)
        cell = options.cell_size_m

        def new_map(pose0):
            return AvoidanceMap(options, center=pose0[:2])

        def insert(local, scan, pose):
            local.insert_visual(scan, pose, mount=mount, table=case.table)

    else:
        cell = float(grid_kwargs["cell_size_m"])

        def new_map(pose0):
            return LocalMap(size_m=local_size_m, pose=pose0, **grid_kwargs)

        def insert(local, scan, pose):
            local.insert_scan(scan, pose=pose, mount=mount)

    for k0 in starts:
        local = new_map(tuple(case.true_poses[k0]))
        (x0, y0), (x1, y1) = local.extent.bounds_m
        cam = compose(case.true_poses[k0], case.robot_from_camera)
        vx, vy = view_cells(
            case.true_status[k0],
            case.true_points[k0],
            cam,
            table=case.table,
            cell_size_m=cell,
            max_range_m=max_range_m,
            window=((x0, y0), (x1, y1)),
        )
        truth = sample_truth(raster.cells, raster.origin, raster.resolution_m, vx, vy)
        known = truth >= 0
        vx, vy, truth = vx[known], vy[known], truth[known]
        if truth.size < 20:
            out.append(None)
            continue
        found = None
        for n in range(max_frames):
            k = k0 + n
            if k >= len(scans):
                break
            insert(local, scans[k], tuple(case.true_poses[k]))
            if agreement_at(local, vx, vy, truth) > RELIABLE_AGREEMENT:
                found = n + 1
                break
        out.append(found)
    return out
