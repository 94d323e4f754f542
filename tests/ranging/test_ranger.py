"""VisualRanger through the Python API, against a numpy brute-force reference and synthetic
images with known edges; every error path."""

from __future__ import annotations

import floorscan
import numpy as np
import pytest
from conftest import affine_table
from floorscan import VisualRanger
from hypothesis import given, settings
from hypothesis import strategies as st


def reference_scan(image, table, columns, d, threshold, margin):
    """Column by column, direct sum of eq. (1): status and first-crossing row per column
    (``refinement="first_crossing"``), with the plan worked out independently from the table."""
    h, _ = image.shape
    out = []
    for c in columns:
        col = image[::-1, c].astype(np.int64)  # k = 0 at the bottom row
        start = h - 1 - margin
        if table.lookup(float(c), float(start)) is None:
            out.append(("invalid", np.nan))
            continue
        top = start
        while top > 0 and table.lookup(float(c), float(top - 1)) is not None:
            top -= 1
        lo, hi = (h - 1 - start) + d, min(h - 1 - top, h - 1 - d)
        if lo > hi:
            out.append(("invalid", np.nan))
            continue
        result = ("no_boundary", float(h - 1 - hi))
        for k in range(lo, hi + 1):
            r = (col[k + 1 : k + d + 1].sum() - col[k - d : k].sum()) / (2 * d)
            if abs(r) > threshold:
                result = ("too_close", float(start)) if k == lo else ("boundary", float(h - 1 - k))
                break
        out.append(result)
    return out


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    d=st.integers(1, 6),
    threshold=st.floats(0, 60),
    n_columns=st.integers(1, 16),
    margin=st.integers(0, 3),
    horizon=st.floats(0, 20),
)
def test_scan_equals_numpy_brute_force(seed, d, threshold, n_columns, margin, horizon):
    rng = np.random.default_rng(seed)
    h, w = 48, 64
    # Blocky columns: runs of constant intensity give edges and plateaus.
    image = np.repeat(rng.integers(0, 256, size=(h // 4, w), dtype=np.uint8), 4, axis=0)
    image = (image.astype(int) + rng.integers(-3, 4, size=(h, w))).clip(0, 255).astype(np.uint8)
    table = affine_table(w, h, 4, horizon)
    ranger = VisualRanger(
        table,
        columns=n_columns,
        half_width_px=d,
        threshold=threshold,
        noise_multiple=0,  # the paper's fixed threshold, as the reference
        contrast=0,
        refinement="first_crossing",
        start={"bottom_margin": margin},
    )
    scan = ranger.scan(image, timestamp=2.5)
    expected = reference_scan(image, table, ranger.columns, d, threshold, margin)
    assert list(scan.status) == [e[0] for e in expected]
    for got, (status, row) in zip(scan.rows, expected):
        if status != "invalid":
            assert got == row
    assert scan.timestamp == 2.5


@pytest.mark.parametrize("floor,obstacle", [(80, 170), (170, 80)])
@pytest.mark.parametrize("refine", ["sub_pixel", "peak"])
def test_step_edges_at_known_rows(floor, obstacle, refine):
    h, w = 48, 64
    edge_rows = 10 + (np.arange(w) % 25)  # first floor row per column
    v = np.arange(h)[:, None]
    image = np.where(v >= edge_rows[None, :], floor, obstacle).astype(np.uint8)
    table = affine_table(w, h)
    scan = VisualRanger(table, columns=w, threshold=20, refinement=refine).scan(image)
    assert set(scan.status) == {"boundary"}
    np.testing.assert_array_equal(scan.rows, edge_rows - 0.5)
    x, y = table.lookup(scan.columns.astype(float), edge_rows - 0.5)
    np.testing.assert_allclose(scan.x, x)
    np.testing.assert_allclose(scan.ranges, np.hypot(x, y))
    np.testing.assert_allclose(scan.bearings, np.arctan2(y, x))


def test_colour_and_uint16_images_scan_like_grey():
    h, w = 48, 64
    v = np.arange(h)[:, None]
    grey = np.where(v >= 30, 60, 200).astype(np.uint8) * np.ones((1, w), np.uint8)
    table = affine_table(w, h)
    r8 = VisualRanger(table, columns=8, threshold=20)
    a = r8.scan(grey)
    b = r8.scan(np.stack([grey] * 3, axis=-1))
    # The threshold is in 8-bit units for every depth: the same frame saved x257 as uint16
    # scans the same with the same ranger (issue 12: it found 3 points instead of 38).
    c = r8.scan(grey.astype(np.uint16) * 257)
    big = np.zeros((h, 2 * w), np.uint8)
    big[:, ::2] = grey
    d = r8.scan(big[:, ::2])  # strided view
    e = r8.scan(np.flipud(np.flipud(grey)))  # negative strides
    for s in (b, c, d, e):
        np.testing.assert_array_equal(s.rows, a.rows)
        np.testing.assert_array_equal(s.status_codes, a.status_codes)


def test_mask_starts_each_column_above_the_bumper():
    h, w = 48, 64
    v = np.arange(h)[:, None]
    image = np.where(v >= 20, 90, 180).astype(np.uint8) * np.ones((1, w), np.uint8)
    image[40:, :] = 250  # a bright bumper in the bottom 8 rows: an edge at row 40
    table = affine_table(w, h)
    plain = VisualRanger(table, columns=4, threshold=20).scan(image)
    # Without a region of interest the bumper's edge sits in the first window: too close.
    assert set(plain.status) == {"too_close"}
    mask = np.ones((h, w), bool)
    mask[40:] = False
    masked = VisualRanger(table, columns=4, threshold=20, mask=mask).scan(image)
    np.testing.assert_array_equal(masked.rows, 19.5)
    margin = VisualRanger(table, columns=4, threshold=20, start={"bottom_margin": 8}).scan(image)
    np.testing.assert_array_equal(margin.rows, 19.5)


@pytest.mark.parametrize(
    "kwargs,error",
    [
        (dict(half_width_px=0), floorscan.OptionError),
        (dict(half_width_px=2.5), floorscan.OptionError),
        (dict(half_width=4), floorscan.OptionError),  # the older spelling: unknown
        (dict(threshold=float("nan")), floorscan.OptionError),
        (dict(threshold=float("inf")), floorscan.OptionError),
        (dict(threshold="high"), floorscan.OptionError),
        (dict(columns=[3, 64]), floorscan.OptionError),
        (dict(columns=0), floorscan.OptionError),
        (dict(columns=[]), floorscan.OptionError),
        (dict(refinement="sometimes"), floorscan.OptionError),
        (dict(start={"bottom_margin": 48}), floorscan.OptionError),
        (dict(start={"sometimes": 2}), floorscan.OptionError),
        (dict(mask=np.ones((3, 3), bool)), floorscan.OptionError),
        (dict(max_range_m=-1.0), floorscan.OptionError),
        (dict(half_width_px=40), floorscan.OptionError),
    ],
)
def test_bad_options_raise_clear_errors(kwargs, error):
    with pytest.raises(error):
        VisualRanger(affine_table(), **kwargs)
    assert issubclass(error, ValueError) and issubclass(error, floorscan.FloorscanError)


@pytest.mark.parametrize(
    "image,error",
    [
        (np.zeros((48, 64), np.float32), floorscan.ImageTypeError),
        (np.zeros((47, 64), np.uint8), floorscan.ImageError),
        (np.zeros((0, 64), np.uint8), floorscan.ImageError),
        (np.zeros((48, 64, 2), np.uint8), floorscan.ImageError),
        ([[0] * 64] * 48, floorscan.ImageTypeError),
    ],
)
def test_bad_images_raise_clear_errors(image, error):
    ranger = VisualRanger(affine_table(), columns=4)
    with pytest.raises(error):
        ranger.scan(image)


def test_non_finite_timestamp_is_rejected():
    with pytest.raises(floorscan.OptionError):
        VisualRanger(affine_table(), columns=4).scan(
            np.zeros((48, 64), np.uint8), timestamp=float("nan")
        )


def test_table_must_be_a_ground_table():
    with pytest.raises(TypeError):
        VisualRanger("table.json")


@pytest.mark.parametrize("width_m,range_m", [(0.03, 1.0), (0.08, 2.0)])
def test_spaced_columns_leave_no_gap_wider_than_the_obstacle(width_m, range_m):
    """Columns placed by floor distance (the default): between two consecutive columns'
    bearings (at their ground nearest the range) no more than the angle the obstacle subtends
    at the range, so at the range no obstacle of the width fits between them; checked by brute
    force on the simulator camera's table (fisheye, so the spacing in pixels varies)."""
    from floorscan.sim import Camera

    table = Camera().ground_table(spacing_px=4)
    cols = VisualRanger(table, columns={"obstacle_width_m": width_m, "range_m": range_m}).columns
    H = table.image_height
    u = np.arange(table.image_width, dtype=float)[:, None]
    v = np.arange(H, dtype=float)[None, :]
    x, y = table.lookup(np.broadcast_to(u, (len(u), H)), np.broadcast_to(v, (len(u), H)))
    gap = np.abs(np.hypot(x, y) - range_m)
    best = np.nanargmin(np.where(np.isfinite(gap), gap, np.inf), axis=1)
    bearing = np.arctan2(y[np.arange(len(u)), best], x[np.arange(len(u)), best])
    reach = 2 * np.arcsin(width_m / (2 * range_m))
    a, b = cols[:-1], cols[1:]
    split = b > a + 1  # adjacent pixel columns cannot be split further
    assert np.abs(bearing[b] - bearing[a])[split].max() <= reach + 1e-12
    # and not needlessly dense: skipping every other column would leave some gap too wide
    assert np.abs(np.diff(bearing[cols[::2]])).max() > reach
    # the default is this rule for a 3 cm leg at 1 m
    default = VisualRanger(table).columns
    spaced = VisualRanger(table, columns={"obstacle_width_m": 0.03, "range_m": 1.0}).columns
    assert np.array_equal(default, spaced)


def test_spaced_columns_from_a_config_file(tmp_path):
    from floorscan.pipeline.config import Config
    from floorscan.pipeline.mapper import ranger_from_config
    from floorscan.sim import Camera

    p = tmp_path / "c.toml"
    p.write_text("[ranger]\ncolumns = { obstacle_width_m = 0.1, range_m = 1.0 }\n")
    table = Camera().ground_table(spacing_px=4)
    r = ranger_from_config(table, Config.load(p))
    assert 8 < len(r.columns) < len(VisualRanger(table).columns)
    p.write_text("[ranger]\ncolumns = { obstacle_width_m = -0.1, range_m = 1.0 }\n")
    with pytest.raises(floorscan.FloorscanError, match="obstacle_width_m"):
        ranger_from_config(table, Config.load(p))
