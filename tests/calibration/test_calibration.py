"""floorscan.calibrate against the simulator's exact image-to-ground mapping: calibration scenes
rendered through its wide-angle (Kannala-Brandt fisheye) lens, both pattern kinds, rotated and
offset patterns; the calibrated region, extrapolation, the horizon; the report, the overlay and
the bad-input errors."""

from __future__ import annotations

import json
import math

import cv2
import floorscan
import numpy as np
import pytest
from floorscan import CalibrationError, GroundTable
from floorscan.calibration import (
    CalibrationReport,
    Pattern,
    calibrate,
    draw_calibration_overlay,
)
from floorscan.calibration.overlay import LINE_COLOUR
from floorscan.sim import CalibrationPattern, Camera, render_calibration


def sim_pattern(p: Pattern) -> CalibrationPattern:
    """The simulator's description of the same pattern (to render it)."""
    if p.kind.value == "checkerboard":
        return CalibrationPattern(
            kind="checkerboard",
            near_left=p.near_left,
            yaw=p.yaw,
            inner_corners=p.counts,
            square=p.step_m,
        )
    return CalibrationPattern(
        kind="lines",
        near_left=p.near_left,
        yaw=p.yaw,
        lines=p.counts,
        spacing=p.step_m,
        line_width=p.line_width_m,
    )


def errors_against_truth(table: GroundTable, camera: Camera, *, within_m: float = 3.0):
    """Distances [m] between the table and the exact mapping at every pixel where the table
    has ground and the true point is within ``within_m`` of the camera."""
    v, u = np.mgrid[0 : table.image_height, 0 : table.image_width].astype(np.float64)
    x, y = table.lookup(u, v)
    tx, ty = camera.pixel_to_ground(u, v)
    ok = np.isfinite(x) & np.isfinite(tx) & (np.hypot(tx, ty) < within_m)
    return np.hypot(x - tx, y - ty)[ok], np.hypot(tx, ty)[ok]


def calibrated(camera: Camera, kind: str, pattern: Pattern = None, **options):
    if pattern is None:
        image, spec = render_calibration(camera, kind=kind)
        pattern = Pattern.from_toml(spec.to_toml())
    else:
        image, _ = render_calibration(camera, sim_pattern(pattern))
    # These tests check the calibrated region around the pattern (the paper's table);
    # tests/calibration/test_calibration_reach.py checks the default table beyond it.
    options.setdefault("coverage", "pattern")
    table, report = calibrate(image, pattern, **options)
    return image, pattern, table, report


@pytest.fixture(scope="module")
def wide320():
    return Camera()  # the simulator's default: 320 x 240 fisheye, about 136 degrees


@pytest.fixture(scope="module")
def wide640():
    return Camera(width=640, height=480)


@pytest.fixture(scope="module")
def checkerboard320(wide320):
    return calibrated(wide320, "checkerboard", spacing_px=4)


# --- accuracy against the simulator's exact mapping ---------------------------------------
def test_checkerboard_scene_matches_the_exact_mapping_within_1_cm(wide320, checkerboard320):
    _image, pattern, table, report = checkerboard320
    e, _ = errors_against_truth(table, wide320)
    assert e.size > 10_000, "the table should cover the pattern's region"
    assert e.max() <= 0.01
    assert np.sqrt(np.mean(e**2)) <= 0.005
    assert report.points_found == pattern.point_count == 63
    assert report.residual_max_cm < 1.0 and report.loo_max_cm < 1.0


def test_line_grid_scene_matches_the_exact_mapping_within_1_cm(wide640):
    _image, pattern, table, report = calibrated(wide640, "lines", spacing_px=4)
    e, _ = errors_against_truth(table, wide640)
    assert e.size > 50_000
    assert e.max() <= 0.01
    assert np.sqrt(np.mean(e**2)) <= 0.005
    # Every line running away, all the rows but maybe a corner crossing beyond the image.
    assert report.points_found >= pattern.point_count - 6


def test_line_grid_too_fine_in_the_distance_keeps_its_near_rows(wide320):
    """At 320 x 240 the farthest lines of the paper's 7 x 9 grid are 3 px apart: the rows that
    resolve are used, labelled from the nearest, and the table is still right."""
    _image, pattern, table, report = calibrated(wide320, "lines", spacing_px=4)
    rows = set(report.indices[:, 1].tolist())
    assert min(rows) == 0 and len(rows) >= 5
    assert set(report.indices[:, 0].tolist()) == set(range(pattern.counts[0]))
    e, _ = errors_against_truth(table, wide320)
    assert e.max() <= 0.015 and np.sqrt(np.mean(e**2)) <= 0.005


@pytest.mark.parametrize(
    "pattern",
    [
        Pattern.checkerboard(inner_corners=(7, 5), square=0.08, near_left=(0.32, 0.42), yaw=0.35),
        Pattern.checkerboard(inner_corners=(6, 6), square=0.08, near_left=(0.30, -0.05), yaw=-0.3),
        Pattern.lines(lines=(5, 5), spacing=0.15, near_left=(0.25, 0.55), yaw=0.3),
        Pattern.lines(
            lines=(6, 4), spacing=0.12, near_left=(0.22, -0.05), yaw=-0.4, line_width=0.015
        ),
    ],
    ids=["board-turned-left", "square-board-right", "lines-turned", "lines-right"],
)
def test_rotated_and_offset_patterns(wide640, pattern):
    _image, _p, table, report = calibrated(wide640, "", pattern, spacing_px=4)
    assert report.points_found == pattern.point_count
    # The pattern's points were matched to the right corners: the table maps each found
    # pixel to its own point, and the whole region agrees with the exact mapping.
    tx, ty = wide640.pixel_to_ground(report.image_points[:, 0], report.image_points[:, 1])
    assert np.max(np.hypot(tx - report.ground_points[:, 0], ty - report.ground_points[:, 1])) < 0.01
    e, _ = errors_against_truth(table, wide640)
    assert e.size > 5_000 and e.max() <= 0.01


# --- the calibrated region, extrapolation, the horizon ------------------------------------
def _outside(points: np.ndarray, outline: np.ndarray) -> np.ndarray:
    hull = cv2.convexHull(outline.astype(np.float32)).reshape(-1, 2)
    return np.array([-cv2.pointPolygonTest(hull, (float(a), float(b)), True) for a, b in points])


def _node_reach(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Distance on the floor from each node to its farthest valid 8-neighbour [m]."""
    xp = np.pad(x, 1, constant_values=np.nan)
    yp = np.pad(y, 1, constant_values=np.nan)
    reach = np.zeros_like(x)
    for dv in (-1, 0, 1):
        for du in (-1, 0, 1):
            nx = xp[1 + dv : 1 + dv + x.shape[0], 1 + du : 1 + du + x.shape[1]]
            ny = yp[1 + dv : 1 + dv + x.shape[0], 1 + du : 1 + du + x.shape[1]]
            reach = np.fmax(reach, np.hypot(nx - x, ny - y))
    return reach


@pytest.mark.parametrize("near_field", [True, False])
def test_no_ground_outside_the_margin_around_the_pattern(wide320, near_field):
    image, spec = render_calibration(wide320, kind="checkerboard")
    pattern = Pattern.from_toml(spec.to_toml())
    table, report = calibrate(
        image, pattern, spacing_px=4, near_field=near_field, coverage="pattern"
    )
    x, y = table.nodes
    ok = np.isfinite(x)
    outline = report.ground_points
    if near_field:  # the floor between the camera and the pattern counts as calibrated
        outline = np.vstack([outline, [[0.0, 0.0]]])
    d = _outside(np.column_stack([x[ok], y[ok]]), outline)
    # Within the margin (one square), or next to a node that is: the table keeps one node
    # around its region so that every pixel inside it interpolates. So the bound is the
    # margin plus the distance on the floor to the farthest neighbouring node.
    assert np.all(d <= pattern.step_m + _node_reach(x, y)[ok] + 1e-9)
    assert np.mean(d <= pattern.step_m) > 0.75  # the ring of extra nodes is a minority
    assert report.margin_m == pattern.step_m and report.near_field == near_field
    # Nothing far away: the whole table lies within 1.3 m for a board ending at 1.0 m.
    assert np.nanmax(np.hypot(x, y)) < 1.3
    # The bottom row (where the range sensor starts) has ground under the pattern only with
    # the near field; the pattern's nearest row is 0.21 m out, the bottom row sees 0.05 m.
    bottom = np.isfinite(x[-1])
    assert bottom.sum() > x.shape[1] / 3 if near_field else not bottom.any()
    e, _ = errors_against_truth(table, wide320)
    assert e.max() <= 0.01


def test_extrapolation_is_limited_and_stays_close_to_the_truth(wide320):
    _image, _pattern, table, report = calibrated(
        wide320, "checkerboard", spacing_px=4, extrapolate=True, max_range_m=3.0
    )
    x, y = table.nodes
    assert np.nanmax(np.hypot(x, y)) <= 3.0
    assert report.extrapolate and report.field_of_view.range_m[1] > 2.5
    # Above the horizon: no ground on the top row.
    assert np.all(np.isnan(x[0]))
    e, r = errors_against_truth(table, wide320)
    # Every node the model sees floor at is kept, with its predicted error: measured 1.1 cm
    # RMS out to 3 m with a 1 m board, and the error bars cover 100 % of the pixels.
    assert np.sqrt(np.mean(e**2)) <= 0.02
    v, u = np.mgrid[0:240, 0:320].astype(float)
    x, y = table.lookup(u, v)
    tx, ty = wide320.pixel_to_ground(u, v)
    bar = table.lookup_error(u, v)
    ok = np.isfinite(x) & np.isfinite(tx) & np.isfinite(bar) & (np.hypot(tx, ty) < 3.0)
    assert np.mean(np.hypot(x - tx, y - ty)[ok] <= bar[ok]) >= 0.9


def test_field_of_view_agrees_with_the_table(checkerboard320):
    _image, _pattern, table, report = checkerboard320
    fov = report.field_of_view
    x, y = table.nodes
    for i in range(len(fov.columns_px)):
        r = np.hypot(x[:, i], y[:, i])
        r = r[np.isfinite(r)]
        if r.size == 0:
            assert math.isnan(fov.near_range_m[i]) and math.isnan(fov.far_range_m[i])
        else:
            assert fov.near_range_m[i] == pytest.approx(r.min())
            assert fov.far_range_m[i] == pytest.approx(r.max())
    # The ground outline contains every pattern point.
    poly = fov.polygon_m.astype(np.float32)
    for gx, gy in report.ground_points:
        assert cv2.pointPolygonTest(poly, (float(gx), float(gy)), False) >= 0
    meta = table.metadata["calibration"]
    assert meta["field_of_view"]["columns_px"] == [int(u) for u in fov.columns_px]
    assert meta["points_found"] == 63


# --- report, metadata, overlay ------------------------------------------------------------
def test_report_summary_metadata_and_files(tmp_path, checkerboard320):
    _image, _pattern, table, report = checkerboard320
    line = report.summary()
    assert "\n" not in line and "63/63 points" in line and "leave-one-out" in line
    assert isinstance(report, CalibrationReport)
    d = json.loads(json.dumps(report.as_dict()))
    assert len(d["points"]) == 63
    assert d["residual_max_cm"] == pytest.approx(100 * np.nanmax(report.residual_m), abs=1e-3)
    path = table.save(tmp_path / "table.json")
    back = GroundTable.load(path)
    assert back == table
    assert back.metadata["calibration"]["summary"] == line
    report.save(tmp_path / "report.json")
    assert json.loads((tmp_path / "report.json").read_text())["points_found"] == 63


def test_residuals_are_what_the_table_says_at_the_points(checkerboard320):
    _image, _pattern, table, report = checkerboard320
    x, y = table.lookup(report.image_points[:, 0], report.image_points[:, 1])
    np.testing.assert_allclose(
        report.residual_m,
        np.hypot(x - report.ground_points[:, 0], y - report.ground_points[:, 1]),
    )
    # Held-out points are predicted less well than fitted ones, but not much worse.
    assert report.loo_rms_cm >= report.residual_rms_cm * 0.99
    assert report.loo_rms_cm <= 2 * report.residual_rms_cm


def test_overlay_lines_lie_on_the_pattern(wide320, checkerboard320):
    image, pattern, table, report = checkerboard320
    rgb = draw_calibration_overlay(image, table, report)
    assert rgb.shape == image.shape + (3,) and rgb.dtype == np.uint8
    v, u = np.nonzero(np.all(rgb == LINE_COLOUR, axis=-1))
    assert u.size > 500
    # Where the overlay draws a line, the true floor point lies on a square's edge.
    tx, ty = wide320.pixel_to_ground(u.astype(float), v.astype(float))
    across, away = pattern.axes()
    dx, dy = tx - pattern.near_left[0], ty - pattern.near_left[1]
    i = (dx * across[0] + dy * across[1]) / pattern.step_m
    j = (dx * away[0] + dy * away[1]) / pattern.step_m
    off = np.minimum(np.abs(i - np.round(i)), np.abs(j - np.round(j))) * pattern.step_m
    # Within one pixel's footprint on the floor (up to ~1.5 cm at a metre at this size).
    assert np.median(off) < 0.006 and np.percentile(off, 95) < 0.02


# --- bad input ----------------------------------------------------------------------------
def test_pattern_not_found_says_how_many_corners_and_what_to_check(wide320):
    rng = np.random.default_rng(0)
    carpet = (90 + rng.integers(0, 40, (240, 320))).astype(np.uint8)
    board = Pattern.checkerboard(inner_corners=(9, 7), square=0.1, near_left=(0.3, 0.4))
    with pytest.raises(CalibrationError, match=r"not found \(no checkerboard corners found.*check"):
        calibrate(carpet, board)
    lines = Pattern.lines(lines=(7, 9), spacing=0.2, near_left=(0.2, 0.6))
    with pytest.raises(CalibrationError, match="not found"):
        calibrate(carpet, lines)


def test_wrong_board_size_and_order_are_errors(wide320, checkerboard320):
    image, pattern, _table, _report = checkerboard320
    smaller = Pattern.checkerboard(inner_corners=(8, 7), square=0.1, near_left=pattern.near_left)
    with pytest.raises(CalibrationError, match="9 x 7 inner corners, the pattern file says 8 x 7"):
        calibrate(image, smaller)
    swapped = Pattern.checkerboard(inner_corners=(7, 9), square=0.1, near_left=pattern.near_left)
    with pytest.raises(CalibrationError, match="check the order of the counts and `yaw`"):
        calibrate(image, swapped)


def test_dark_and_blurred_images_are_errors(checkerboard320):
    image, pattern, _table, _report = checkerboard320
    with pytest.raises(CalibrationError, match="too dark"):
        calibrate((image * 0.04).astype(np.uint8), pattern)
    with pytest.raises(CalibrationError, match="in focus"):
        calibrate(cv2.GaussianBlur(image, (0, 0), 6), pattern)


@pytest.mark.parametrize(
    "pattern",
    [
        Pattern.checkerboard(inner_corners=(3, 3), square=0.1, near_left=(0.4, 0.1)),
        Pattern.lines(lines=(3, 3), spacing=0.2, near_left=(0.3, 0.2)),
    ],
    ids=["board", "lines"],
)
def test_too_few_points_is_an_error(wide320, pattern):
    image, _ = render_calibration(wide320, sim_pattern(pattern))
    with pytest.raises(CalibrationError, match="too few pattern points.*9 found"):
        calibrate(image, pattern)


def test_wrongly_turned_description_is_refused(checkerboard320):
    """The board lies with its 9-corner rows across the view; a file saying it is turned by
    90 degrees cannot be matched (its rows would have to run away from the camera)."""
    image, pattern, _table, _report = checkerboard320
    turned = Pattern.checkerboard(
        inner_corners=(9, 7), square=0.1, near_left=pattern.near_left, yaw=math.pi / 2
    )
    with pytest.raises(CalibrationError, match="does not run as the pattern file says"):
        calibrate(image, turned)


def test_a_fit_that_mirrors_the_floor_is_refused(checkerboard320):
    """A camera above the floor never sees it mirrored: if the points were matched the wrong
    way round (here: the pattern's y flipped), the fit is refused rather than mirroring the
    table."""
    from floorscan.calibration.detect import detect
    from floorscan.calibration.lens_family import DEFAULT_FAMILIES
    from floorscan.calibration.model_choice import choose

    image, pattern, _table, _report = checkerboard320
    det = detect(image, pattern)
    mirrored = det.ground_points * np.array([1.0, -1.0])
    # No rigid camera above the floor sees the mirrored points: either no family finds a
    # pose above the floor, or the best fit maps the image onto a mirrored floor.
    from floorscan.calibration.build import _check_chirality

    with pytest.raises(CalibrationError, match="mirrored"):
        choice = choose(det.image_points, mirrored, (320, 240), DEFAULT_FAMILIES)
        _check_chirality(choice.best.fit.model, det.image_points)


def test_options_are_validated(checkerboard320):
    image, pattern, _table, _report = checkerboard320
    with pytest.raises(floorscan.OptionError, match="spacing_px"):
        calibrate(image, pattern, spacing_px=0)
    with pytest.raises(floorscan.OptionError, match="max_range_m"):
        calibrate(image, pattern, max_range_m=-1.0)
    with pytest.raises(floorscan.ImageTypeError):
        calibrate(image.astype(np.float32), pattern)
    with pytest.raises(TypeError):
        calibrate(image, 42)


def test_top_level_reexport():
    assert floorscan.calibrate is calibrate
    assert floorscan.Pattern is Pattern
