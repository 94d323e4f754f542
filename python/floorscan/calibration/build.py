"""From images of a known floor pattern to a ground lookup table (paper III.B): detect the
pattern's points, fit a physical camera model (lens family + pose above the floor,
:mod:`.camera_fit`, chosen by held-out error, :mod:`.model_choice`), fill the table's nodes from
it out to the range sensor's maximum range, with a predicted error per node
(:mod:`.uncertainty`), keep the nodes it can be trusted at, and measure the result."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from .._atomic import PathLike
from ..errors import CalibrationError, ImageError, OptionError
from ..ranging.ground_table import GroundTable
from .camera_fit import refine
from .detect import Detection, detect, to_uint8
from .intrinsics import Intrinsics
from .model_choice import Choice, choose
from .options import CalibrationOptions, Coverage
from .pattern import Pattern
from .region import convex_hull, field_of_view, near_region, node_grid
from .report import CalibrationReport, RangeRing, range_rings
from .uncertainty import family_weights, inflation, node_errors

ImageOrImages = Union[np.ndarray, Sequence[np.ndarray]]


@dataclass
class Views:
    """The pattern points of every image, together: ``image_points`` (M, 2) [px],
    ``ground_points`` (M, 2) [m], ``indices`` (M, 2) (i across, j away), ``view`` (M,) the
    image each came from, and the detections."""

    image_points: np.ndarray
    ground_points: np.ndarray
    indices: np.ndarray
    view: np.ndarray
    detections: List[Detection]
    image_size: Tuple[int, int]


def detect_views(
    images: Sequence[np.ndarray], patterns: Sequence[Pattern], offsets_m: Sequence[float]
) -> Views:
    """Detects the pattern in each image; the pattern of image k lies ``offsets_m[k]`` [m]
    further away (+x) than its file says (the robot backed up by that much)."""
    dets, uvs, gs, idx, view = [], [], [], [], []
    size = None
    for k, (image, pattern, off) in enumerate(zip(images, patterns, offsets_m)):
        grey = to_uint8(image)
        h, w = grey.shape
        if size is not None and (w, h) != size:
            raise ImageError(
                f"calibration image {k + 1} is {w} x {h}, image 1 is {size[0]} x {size[1]}: all "
                "must come from the same camera at the same resolution"
            )
        size = (w, h)
        try:
            det = detect(grey, pattern)
        except CalibrationError as e:
            if len(images) == 1:
                raise
            raise CalibrationError(f"calibration image {k + 1}: {e}") from None
        dets.append(det)
        uvs.append(det.image_points)
        gs.append(det.ground_points + np.array([float(off), 0.0]))
        idx.append(det.indices)
        view.append(np.full(len(det.image_points), k))
    assert size is not None
    return Views(np.vstack(uvs), np.vstack(gs), np.vstack(idx), np.concatenate(view), dets, size)


def calibrate(
    image: ImageOrImages,
    pattern: Union[Pattern, PathLike, Sequence[Union[Pattern, PathLike]]],
    *,
    intrinsics: Optional[Union[Intrinsics, PathLike]] = None,
    offsets_m: Optional[Sequence[float]] = None,
    extrapolate: bool = False,
    **options: Any,
) -> Tuple[GroundTable, CalibrationReport]:
    """Builds a ground table from one or more images of a calibration pattern on the floor.

    Args:
        image: (H, W) uint8 or uint16 grey image (or (H, W, 3) colour) from the robot's
            camera, or a list of them (the pattern moved, or the robot backed up).
        pattern: a :class:`Pattern` or the path of its ``pattern.toml``; or one per image.
        offsets_m: per image, how much further away (+x) [m] than its pattern file says the
            pattern lay (the robot backed up by that distance). Default: 0 for every image.
        intrinsics: known lens intrinsics (an :class:`Intrinsics` or the path of an OpenCV
            FileStorage YAML/XML or ROS camera_info YAML): only the camera's pose is fitted.
        options: the fields of :class:`CalibrationOptions` as keywords (``spacing_px``,
            ``coverage``, ``max_error_fraction``, ``min_error_m``, ``max_range_m``,
            ``horizon_margin_rad``, ``families``, ``margin_m``, ``near_field``,
            ``leave_one_out``); its defaults apply to those not given.
        extrapolate: True is ``coverage="all"`` (kept for older callers).

    Returns:
        ``(table, report)``: a :class:`floorscan.GroundTable` for images of this size (pixel ->
        ground point in the camera ground frame, x forward, y left [m]) with a predicted error
        per node (``table.error_m``), carrying ``report.metadata()`` under
        ``metadata["calibration"]``; and the :class:`CalibrationReport`.

    Raises:
        floorscan.CalibrationError: pattern not found (the message says how many points were
            found and what to check), too few points, a mirrored pattern, intrinsics for
            another image size.
        floorscan.ConfigError: a pattern file with missing, unknown or ill-typed keys.
        floorscan.ImageError: not an image, or images of different sizes.

    A simulated photo of the paper's line grid (a real photo and its pattern file,
    ``calibrate(image, "pattern.toml")``, go the same way):

    >>> from floorscan.calibration import Pattern, calibrate
    >>> from floorscan.sim import Camera, render_calibration
    >>> image, laid = render_calibration(Camera(), kind="lines")
    >>> table, report = calibrate(image, Pattern.from_toml(laid.to_toml()))
    >>> (table.image_width, table.image_height), report.coverage
    ((320, 240), 'trusted')
    >>> bool(abs(report.residual_m[report.used]).max() < 0.02)   # every used point within 2 cm
    True
    >>> print(report.summary())
    45/63 points (line grid ...); residual RMS ... cm ...
    """
    if extrapolate:
        options["coverage"] = Coverage.ALL
    known_options = set(CalibrationOptions.__dataclass_fields__)
    unknown = sorted(set(options) - known_options)
    if unknown:
        raise OptionError(
            f"unknown calibration option(s) {unknown} (known: {sorted(known_options)})"
        )
    if options.get("families") is None:
        options.pop("families", None)
    opts = CalibrationOptions(**options)
    images = [image] if isinstance(image, np.ndarray) else list(image)
    if not images:
        raise ImageError("no calibration image given")
    patterns = _patterns(pattern, len(images))
    offsets = [0.0] * len(images) if offsets_m is None else [float(o) for o in offsets_m]
    if len(offsets) != len(images) or not all(np.isfinite(offsets)):
        raise CalibrationError(
            f"offsets_m needs one finite value per image ({len(images)}), got {offsets_m!r}"
        )
    clock = _Clock()
    views = detect_views(images, patterns, offsets)
    w, h = views.image_size
    clock.lap("detect")
    known = _intrinsics(intrinsics)
    if known is not None:
        known.check_size((w, h))
    uv, g = views.image_points, views.ground_points
    choice = choose(
        uv,
        g,
        (w, h),
        (known.family.name,) if known is not None else opts.families,
        lens=None if known is None else known.params,
    )
    model = choice.best.fit.model
    chirality = _check_chirality(model, uv[choice.used])
    clock.lap("fit")
    u, v = node_grid((w, h), opts.spacing_px)
    margin = opts.horizon_margin_rad
    x, y = model.ground(u, v, min_depression_rad=margin)
    det = model.jacobian_det(u, v)
    valid = np.isfinite(x) & (np.sign(det) == chirality)
    valid &= np.hypot(x - model.centre_m[0], y - model.centre_m[1]) <= opts.max_range_m
    alpha = inflation(choice, uv, g, fold_margin_px=float(opts.spacing_px))
    others, weights = family_weights(choice)
    bar, _sigma, _spread, _interp = node_errors(
        choice.best.fit,
        [c.fit.model for c in others],
        u,
        v,
        opts.spacing_px,
        min_depression_rad=margin,
        alpha=alpha,
        weights=weights,
    )
    rng = np.hypot(np.nan_to_num(x), np.nan_to_num(y))
    trusted = valid & (bar <= np.maximum(opts.max_error_fraction * rng, opts.min_error_m))
    pattern_margin = patterns[0].extent_m if opts.margin_m is None else float(opts.margin_m)
    if opts.coverage is Coverage.TRUSTED:
        keep = trusted
    elif opts.coverage is Coverage.ALL:
        keep = valid
    else:
        outline = g[choice.used]
        if opts.near_field:
            outline = np.vstack([outline, model.centre_m[None, :2]])
        keep = valid & near_region(x, y, convex_hull(outline), pattern_margin)
    x, y = np.where(keep, x, np.nan), np.where(keep, y, np.nan)
    table = GroundTable.from_arrays(x, y, image_width=w, image_height=h, spacing_px=opts.spacing_px)
    table = table.with_errors(np.where(keep & np.isfinite(bar), bar, np.nan))
    clock.lap("table")
    tx, ty = table.lookup(uv[:, 0], uv[:, 1])
    residual = np.hypot(tx - g[:, 0], ty - g[:, 1])
    mx, my = model.ground(uv[:, 0], uv[:, 1])
    interpolation = np.column_stack([np.nan_to_num(tx - mx), np.nan_to_num(ty - my)])
    if opts.leave_one_out:
        loo, loo_kind = _refit_loo(choice, uv, g, (w, h), interpolation, known), "refit"
    else:
        loo, loo_kind = residual.copy(), "residual"
    clock.lap("leave_one_out")
    fov = field_of_view(table)
    all_bar = np.where(valid, bar, np.nan)
    rings = range_rings(rng, all_bar, valid, keep, opts.max_range_m)
    clock.lap("report")
    report = CalibrationReport(
        pattern=patterns[0],
        method=", ".join(sorted({d.method for d in views.detections})),
        image_size=(w, h),
        points_expected=sum(p.point_count for p in patterns),
        image_points=uv,
        ground_points=g,
        indices=views.indices,
        residual_m=residual,
        loo_m=loo,
        used=choice.used,
        model=model,
        model_name=choice.best.name,
        candidates=[(c.name, c.held_out_px) for c in choice.candidates],
        plausible=[c.name for c in choice.plausible],
        error_inflation=alpha,
        noise_px=choice.best.fit.noise_px,
        field_of_view=fov,
        spacing_px=opts.spacing_px,
        coverage=opts.coverage.value,
        max_error_fraction=opts.max_error_fraction,
        max_range_m=opts.max_range_m,
        rings=rings,
        intrinsics_given=known is not None,
        views=len(images),
        margin_m=pattern_margin,
        near_field=opts.near_field,
        loo_kind=loo_kind,
        timings_s=clock.laps,
        notes=[
            f"point (i={i}, j={j}) of image {k + 1} left out of the fit as an outlier"
            for (i, j), k in zip(views.indices[~choice.used], views.view[~choice.used])
        ],
    )
    meta = dict(table.metadata)
    meta["source"] = "floorscan calibrate"
    meta["calibration"] = report.metadata()
    return table.with_metadata(meta), report


def _patterns(pattern, n: int) -> List[Pattern]:
    if isinstance(pattern, (list, tuple)):
        if len(pattern) not in (1, n):
            raise CalibrationError(
                f"{n} calibration images need one pattern or one per image, got {len(pattern)}"
            )
        ps = [Pattern.resolve(p) for p in pattern]
        return ps * n if len(ps) == 1 else ps
    return [Pattern.resolve(pattern)] * n


def _intrinsics(intrinsics) -> Optional[Intrinsics]:
    if intrinsics is None or isinstance(intrinsics, Intrinsics):
        return intrinsics
    return Intrinsics.load(intrinsics)


class _Clock:
    """Seconds spent in each stage (``laps``), for the report and the benchmark."""

    def __init__(self) -> None:
        self.laps: Dict[str, float] = {}
        self._t = time.perf_counter()

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.laps[name] = now - self._t
        self._t = now


def _check_chirality(model, uv: np.ndarray) -> float:
    """Sign of the image-to-floor Jacobian determinant at the pattern. A camera above the floor
    sees it mirrored (image right is ground right, image down is towards the camera): the sign
    is negative. A positive sign means the pattern file describes a mirror image."""
    s = float(np.sign(np.nansum(np.sign(model.jacobian_det(uv[:, 0], uv[:, 1])))))
    if s >= 0 or model.height_m <= 0:
        raise CalibrationError(
            "the fitted floor is mirrored: the pattern's points run the wrong way round for a "
            "camera looking down at the floor; check `near_left`, `yaw` and the pattern's "
            "counts (across = left to right in the image, away = from the camera)"
        )
    return s


def _refit_loo(
    choice: Choice,
    uv: np.ndarray,
    g: np.ndarray,
    image_size: Tuple[int, int],
    offset: np.ndarray,
    known: Optional[Intrinsics],
) -> np.ndarray:
    """Floor error [m] at each point of the model refitted without it (plus ``offset`` (M, 2)
    [m], the table's interpolation error there); outliers get the fitted model's error."""
    fit = choice.best.fit
    out = np.empty(len(uv))
    for i in range(len(uv)):
        model = fit.model
        if choice.used[i]:
            keep = choice.used & (np.arange(len(uv)) != i)
            model = refine(
                fit.model,
                uv[keep],
                g[keep],
                image_size,
                fix_lens=known is not None,
                max_iterations=15,
                noise_px=fit.noise_px,
            ).model
        x, y = model.ground(uv[i, 0], uv[i, 1])
        out[i] = float(np.hypot(x + offset[i, 0] - g[i, 0], y + offset[i, 1] - g[i, 1]))
    return np.where(np.isfinite(out), out, np.inf)


__all__ = ["RangeRing", "Views", "calibrate", "detect_views"]
