"""From one image of a known floor pattern to a ground lookup table (paper III.B): detect the
pattern's points, fit the image-to-floor model, evaluate it on the table's nodes within the region
it can be trusted, and measure the result."""

from __future__ import annotations

import time
from typing import Dict, Optional, Tuple, Union

import numpy as np

from .._atomic import PathLike
from ..errors import CalibrationError
from ..ground_table import GroundTable
from .detect import Detection, detect, to_uint8
from .fit import Fit, fit_robust, fit_spec
from .options import CalibrationOptions
from .pattern import Pattern
from .region import convex_hull, field_of_view, model_nodes, near_region, node_grid
from .report import CalibrationReport


def calibrate(
    image: np.ndarray,
    pattern: Union[Pattern, PathLike],
    *,
    spacing_px: int = 8,
    extrapolate: bool = False,
    margin_m: Optional[float] = None,
    near_field: bool = True,
    max_range_m: float = 10.0,
    leave_one_out: bool = True,
) -> Tuple[GroundTable, CalibrationReport]:
    """Builds a ground table from one image of a calibration pattern lying on the floor.

    Args:
        image: (H, W) uint8 or uint16 grey image (or (H, W, 3) colour) from the robot's camera.
        pattern: a :class:`Pattern` or the path of its ``pattern.toml``.
        spacing_px, extrapolate, margin_m, near_field, max_range_m, leave_one_out: see
            :class:`CalibrationOptions`.

    Returns:
        ``(table, report)``: a :class:`floorscan.GroundTable` for images of this size (pixel ->
        ground point in the camera ground frame, x forward, y left [m]; "no ground" outside the
        calibrated region unless ``extrapolate``) carrying ``report.metadata()`` under
        ``metadata["calibration"]``, and the :class:`CalibrationReport`.

    Raises:
        floorscan.CalibrationError: pattern not found (the message says how many points were
            found and what to check), too few points, or a fit that mirrors the floor.
        floorscan.ConfigError: a pattern file with missing, unknown or ill-typed keys.
        floorscan.ImageError: not an image.

    The model is a central camera with free radial distortion looking at a plane (no pinhole
    assumption: fisheye lenses work); see :mod:`floorscan.calibration.model`.
    """
    opts = CalibrationOptions(
        spacing_px=spacing_px,
        extrapolate=extrapolate,
        margin_m=margin_m,
        near_field=near_field,
        max_range_m=max_range_m,
        leave_one_out=leave_one_out,
    )
    pattern = Pattern.resolve(pattern)
    clock = _Clock()
    grey = to_uint8(image)
    h, w = grey.shape
    det = detect(grey, pattern)
    clock.lap("detect")
    best, fits, used = fit_robust(det.image_points, det.ground_points, (w, h))
    chirality = _check_chirality(best, det)
    clock.lap("fit")
    margin = pattern.extent_m if opts.margin_m is None else float(opts.margin_m)
    u, v = node_grid((w, h), opts.spacing_px)
    x, y = model_nodes(
        best.model, u, v, image_size=(w, h), chirality=chirality, max_range_m=opts.max_range_m
    )
    if not opts.extrapolate:
        outline = det.ground_points
        if opts.near_field:
            outline = np.vstack([outline, [[0.0, 0.0]]])
        keep = near_region(x, y, convex_hull(outline), margin)
        x, y = np.where(keep, x, np.nan), np.where(keep, y, np.nan)
    table = GroundTable.from_arrays(x, y, image_width=w, image_height=h, spacing_px=opts.spacing_px)
    clock.lap("table")
    tx, ty = table.lookup(det.image_points[:, 0], det.image_points[:, 1])
    residual = np.hypot(tx - det.ground_points[:, 0], ty - det.ground_points[:, 1])
    # The table's own interpolation error at each point, added to the leave-one-out
    # prediction of the model, so both figures describe the table.
    mx, my = best.model.ground(det.image_points[:, 0], det.image_points[:, 1])
    interpolation = np.column_stack([np.nan_to_num(tx - mx), np.nan_to_num(ty - my)])
    if opts.leave_one_out:
        loo, loo_kind = _refit_loo(best, det, used, (w, h), interpolation), "refit"
    else:
        loo = residual.copy()
        loo[used] = best.loo_px * _metres_per_px(best, det)[used]
        loo_kind = "linearised"
    clock.lap("leave_one_out")
    fov = field_of_view(table)
    clock.lap("report")
    report = CalibrationReport(
        pattern=pattern,
        method=det.method,
        image_size=(w, h),
        points_expected=pattern.point_count,
        image_points=det.image_points,
        ground_points=det.ground_points,
        indices=det.indices,
        residual_m=residual,
        loo_m=loo,
        used=used,
        model=best.model,
        model_name=best.spec.name,
        candidates=[(f.spec.name, _rms(f.loo_px)) for f in fits],
        field_of_view=fov,
        spacing_px=opts.spacing_px,
        extrapolate=opts.extrapolate,
        margin_m=margin,
        near_field=opts.near_field,
        loo_kind=loo_kind,
        timings_s=clock.laps,
        notes=[
            f"point (i={i}, j={j}) left out of the fit as an outlier" for i, j in det.indices[~used]
        ],
    )
    meta = dict(table.metadata)
    meta["source"] = "floorscan calibrate"
    meta["calibration"] = report.metadata()
    return table.with_metadata(meta), report


class _Clock:
    """Seconds spent in each stage (``laps``), for the report and the benchmark."""

    def __init__(self) -> None:
        self.laps: Dict[str, float] = {}
        self._t = time.perf_counter()

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.laps[name] = now - self._t
        self._t = now


def _rms(a: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.asarray(a) ** 2)))


def _check_chirality(fit: Fit, det: Detection) -> float:
    """Sign of the image-to-floor Jacobian determinant at the pattern. A camera above the floor
    sees it mirrored (image right is ground right, image down is towards the camera): the sign
    is negative. A positive sign means the pattern file describes a mirror image."""
    jac = fit.model.jacobian(det.image_points[:, 0], det.image_points[:, 1])
    det_sign = np.sign(jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0])
    s = float(np.sign(np.sum(det_sign)))
    if s >= 0:
        raise CalibrationError(
            "the fitted floor is mirrored: the pattern's points run the wrong way round for a "
            "camera looking down at the floor; check `near_left`, `yaw` and the pattern's "
            "counts (across = left to right in the image, away = from the camera)"
        )
    return s


def _metres_per_px(fit: Fit, det: Detection) -> np.ndarray:
    jac = fit.model.jacobian(det.image_points[:, 0], det.image_points[:, 1])
    return np.sqrt(np.abs(jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]))


def _refit_loo(
    best: Fit, det: Detection, used: np.ndarray, image_size: Tuple[int, int], offset: np.ndarray
) -> np.ndarray:
    """Ground error [m] at each point of the model refitted without it (plus ``offset``
    (M, 2) [m], the table's interpolation error there); points left out of the fit as
    outliers get the fitted model's error."""
    uv, g = det.image_points, det.ground_points
    out = np.empty(len(uv))
    for i in range(len(uv)):
        if not used[i]:
            x, y = best.model.ground(uv[i, 0], uv[i, 1])
            out[i] = float(np.hypot(x + offset[i, 0] - g[i, 0], y + offset[i, 1] - g[i, 1]))
            continue
        keep = used & (np.arange(len(uv)) != i)
        f = fit_spec(
            uv[keep],
            g[keep],
            image_size,
            best.spec,
            best.model,
            max_iterations=20,
            rounds=1,
            with_loo=False,
        )
        x, y = f.model.ground(uv[i, 0], uv[i, 1])
        out[i] = float(np.hypot(x + offset[i, 0] - g[i, 0], y + offset[i, 1] - g[i, 1]))
    return np.where(np.isfinite(out), out, np.inf)
