"""The appearance ranger (floorscan.AppearanceRanger) and the fused ranger: against an
independent numpy implementation of the same method on random textured floors with
obstacles, against known boundaries, and on bad input."""

from __future__ import annotations

import floorscan as fs
import numpy as np
import pytest
from appearance_reference import appearance_scan
from floorscan.evaluation.floor_masks import image_row_table
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import ranger_from_config
from floorscan.ranging.fused import FusedRanger

W, H = 96, 72


def textured_scene(seed: int):
    """A floor of random tiles from a small palette with noise, and obstacles of other colours
    (random boxes, one touching the bottom)."""
    rng = np.random.default_rng(seed)
    palette = rng.integers(60, 200, size=(3, 3))
    tiles = rng.integers(0, 3, size=(H // 6 + 1, W // 6 + 1))
    img = palette[np.kron(tiles, np.ones((6, 6), int))[:H, :W]]
    obstacle = np.zeros((H, W), bool)
    for _ in range(4):
        u0, u1 = sorted(rng.integers(0, W, 2))
        base = int(rng.integers(5, H - 12))
        obstacle[:base, u0 : u1 + 1] = True
    u = int(rng.integers(0, W - 6))
    obstacle[:, u : u + 6] = rng.random() < 0.5
    colours = rng.integers(0, 256, size=(4, 3))
    img = np.where(obstacle[..., None], colours[rng.integers(0, 4, size=(H, W))], img)
    img = img + rng.integers(-5, 6, size=img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("features", ["colour", "colour_and_texture"])
def test_matches_an_independent_numpy_implementation(seed, features):
    img = textured_scene(seed)
    opts = dict(min_floor_share=0.01, intensity_reach_bins=1 + seed % 2, min_run_px=2 + seed % 3)
    width_fraction = (1.0, 0.5, 0.3)[seed % 3]
    r = fs.AppearanceRanger(
        image_row_table(W, H),
        columns=W,
        start={"bottom_margin": 0},
        max_range_m=None,
        features=features,
        reference_fraction=0.15,
        reference_width_fraction=width_fraction,
        patch_half_width_px=seed % 3,
        **opts,
    )
    scan = r.scan(img)
    status, rows = appearance_scan(
        img,
        np.arange(W),
        start_row=H - 1,
        reference_fraction=0.15,
        reference_width_fraction=width_fraction,
        min_share=opts["min_floor_share"],
        intensity_reach=opts["intensity_reach_bins"],
        patch_half_width=seed % 3,
        min_run=opts["min_run_px"],
        texture=features == "colour_and_texture",
    )
    np.testing.assert_array_equal(scan.status_codes, status)
    np.testing.assert_array_equal(scan.rows, rows)
    assert np.all((scan.confidence >= 0) & (scan.confidence <= 1))


def test_a_wall_of_another_colour_over_a_plain_floor():
    img = np.zeros((H, W, 3), np.uint8)
    img[40:] = (120, 110, 90)
    img[:40] = (30, 60, 160)
    r = fs.AppearanceRanger(image_row_table(W, H), columns=8, max_range_m=None)
    scan = r.scan(img, timestamp=2.0)
    assert list(scan.status) == ["boundary"] * 8
    np.testing.assert_array_equal(scan.rows, 39.5)
    assert scan.timestamp == 2.0
    assert r.frames_learned == 1
    r.reset_model()
    assert r.frames_learned == 0
    # Grey input: every channel the same; a wall more than one intensity bin darker.
    grey = np.full((H, W), 106, np.uint8)
    grey[:40] = 30
    np.testing.assert_array_equal(r.scan(grey).rows, 39.5)


def test_bad_input_raises_floorscan_errors():
    r = fs.AppearanceRanger(image_row_table(W, H), columns=8)
    with pytest.raises(fs.ImageError):
        r.scan(np.zeros((H, W + 1, 3), np.uint8))
    with pytest.raises(fs.ImageTypeError):
        r.scan(np.zeros((H, W, 3), np.float32))
    with pytest.raises(fs.ImageError):
        r.scan(np.zeros((H, W, 2), np.uint8))
    for bad in (
        dict(min_floor_share=0.0),
        dict(adaptation_rate=1.5),
        dict(reference_fraction=0.9),
        dict(min_run_px=0),
        dict(intensity_reach_bins=0),
        dict(min_run=3),  # the older spelling: unknown
        dict(features="hsv"),
        dict(columns=0),
    ):
        with pytest.raises(fs.OptionError):
            fs.AppearanceRanger(image_row_table(W, H), **bad)


def grout_frame() -> np.ndarray:
    """A plain floor with a thin grey grout line at row 60 (in the reference band: floor to the
    appearance model, an edge to the edge ranger) and a blue wall from row 30 up."""
    img = np.zeros((H, W, 3), np.uint8)
    img[:] = (150, 140, 120)
    img[60] = (90, 90, 90)
    img[:30] = (30, 60, 160)
    return img


def grout_rangers(table):
    """(edge, appearance) rangers for :func:`grout_frame`: the edge ranger with a fixed
    threshold, so that the grout line (R = 12.5) is an edge."""
    edge = fs.VisualRanger(
        table,
        columns=8,
        max_range_m=None,
        threshold=5,
        noise_multiple=0,
        contrast=0,
        half_width_px=2,
    )
    app = fs.AppearanceRanger(table, columns=8, max_range_m=None, reference_fraction=0.3)
    return edge, app


def test_fused_takes_nearby_edges_and_ignores_grout_lines():
    img = grout_frame()
    table = image_row_table(W, H)
    edge, app = grout_rangers(table)
    e, a = edge.scan(img), app.scan(img)
    assert np.all(e.rows > 55)  # the edge ranger stops at the grout line
    np.testing.assert_array_equal(a.rows, 29.5)
    fused = FusedRanger(edge, app, snap_rows=3).scan(img)
    np.testing.assert_array_equal(fused.rows, 29.5)
    # Edge and appearance agree at the wall once the grout line is gone: the edge's row wins.
    img[60] = img[61]
    fused = FusedRanger(edge, app, snap_rows=3).scan(img)
    np.testing.assert_array_equal(fused.rows, edge.scan(img).rows)
    with pytest.raises(fs.OptionError):
        FusedRanger(edge, app, snap_rows=-1)
    with pytest.raises(fs.OptionError):
        FusedRanger(edge, fs.AppearanceRanger(table, columns=4), snap_rows=1)


def test_fused_keeps_a_textured_floor_through_frames_that_cannot_tell():
    # Frame 1: a grout line at row 60 below a blue wall from row 30 up; the edge ranger stops
    # at the grout in every column, 30 rows below the appearance boundary: a textured floor.
    # Frame 2: the same floor to the top of the image; the appearance ranger sees floor
    # throughout, so the frame has no column to compare: it keeps frame 1's judgement and the
    # grout line is not an obstacle. On its own (or after reset_model) the frame is plain and
    # the edge ranger's boundary stands (a grey obstacle on a grey floor looks like this).
    wall = grout_frame()
    open_floor = wall.copy()
    open_floor[:30] = (150, 140, 120)
    table = image_row_table(W, H)

    def fused():
        return FusedRanger(*grout_rangers(table), snap_rows=3)

    r = fused()
    assert not r.textured
    np.testing.assert_array_equal(r.scan(wall).rows, 29.5)
    assert r.textured
    after = r.scan(open_floor)
    assert r.textured
    assert np.all(after.status == "no_boundary")
    alone = fused().scan(open_floor)
    assert np.all(alone.status == "boundary") and np.all(alone.rows > 55)
    r.reset_model()
    assert not r.textured
    assert np.all(r.scan(open_floor).status == "boundary")


@pytest.mark.parametrize("share", [-0.1, 1.5, float("nan")])
def test_fused_texture_share_out_of_range_is_an_option_error(share):
    table = image_row_table(W, H)
    edge = fs.VisualRanger(table, columns=8, max_range_m=None)
    app = fs.AppearanceRanger(table, columns=8, max_range_m=None)
    with pytest.raises(fs.OptionError, match="texture_share"):
        FusedRanger(edge, app, texture_share=share)


def test_fused_texture_share_comes_from_the_config():
    cfg = Config().with_overrides({"ranger.kind": "fused", "appearance.texture_share": 0.4})
    r = ranger_from_config(image_row_table(W, H), cfg, max_range_m=None, columns=8)
    assert r.options["texture_share"] == 0.4


@pytest.mark.parametrize("fraction", [-0.1, 1.5, float("nan")])
def test_fused_snap_fraction_out_of_range_is_an_option_error(fraction):
    table = image_row_table(W, H)
    edge = fs.VisualRanger(table, columns=8, max_range_m=None)
    app = fs.AppearanceRanger(table, columns=8, max_range_m=None)
    with pytest.raises(fs.OptionError, match="snap_fraction"):
        FusedRanger(edge, app, snap_fraction=fraction)


def test_fused_snap_scales_with_the_image_height():
    """An edge 8 rows below the appearance boundary (a wall's grey skirting the colour model
    takes for floor): taken when 8 rows lie within snap_fraction x the height, else the
    appearance boundary stands. The same scene at twice the size needs the same fraction."""
    for scale in (1, 2):
        h, w = H * scale, W * scale
        img = np.zeros((h, w, 3), np.uint8)
        img[:] = (150, 140, 120)
        img[: 30 * scale] = (30, 60, 160)  # blue wall
        # skirting: the floor's colour 12 levels brighter (one intensity bin: floor to the
        # appearance model; a step of 12 to the edge ranger)
        img[30 * scale : 38 * scale] = (162, 152, 132)
        table = image_row_table(w, h)
        opts = dict(columns=8, max_range_m=None)
        edge = fs.VisualRanger(table, threshold=5, noise_multiple=0, contrast=0, **opts)
        app = fs.AppearanceRanger(table, reference_fraction=0.3, min_floor_share=0.003, **opts)
        e, a = edge.scan(img), app.scan(img)
        gap = float(np.median(e.rows - a.rows))
        assert gap > 3 * scale  # the edge lies below the appearance boundary
        near = FusedRanger(edge, app, snap_rows=0, snap_fraction=1.2 * gap / h).scan(img)
        far = FusedRanger(edge, app, snap_rows=0, snap_fraction=0.8 * gap / h).scan(img)
        np.testing.assert_array_equal(near.rows, e.rows)
        np.testing.assert_array_equal(far.rows, a.rows)


@pytest.mark.parametrize("kind", ["edge", "appearance", "fused"])
def test_config_kind_builds_that_ranger(kind):
    cfg = Config().with_overrides({"ranger.kind": kind, "appearance.min_run": 4})
    r = ranger_from_config(image_row_table(W, H), cfg, max_range_m=None, columns=64)
    expected = {"edge": fs.VisualRanger, "appearance": fs.AppearanceRanger, "fused": FusedRanger}
    assert isinstance(r, expected[kind])
    assert len(r.scan(textured_scene(0))) == 64
    with pytest.raises(fs.FloorscanError):
        ranger_from_config(image_row_table(W, H), Config().with_overrides({"ranger.kind": "x"}))


def test_boundary_samples_teach_the_floor_through_the_python_api():
    from floorscan.ranging.appearance import NO_SAMPLE

    table = fs.GroundTable.from_camera(
        fs.Lens.equidistant(f=140, cx=159.5, cy=119.5),
        fs.CameraMount(height_m=0.4, tilt_rad=0.6),
        image_width=320,
        image_height=240,
    )
    # the reference relearned every frame: the patch stays floor only as driven-over floor
    ranger = fs.AppearanceRanger(table, columns=16, driven_floor_samples=8, adaptation_rate=1.0)
    image = np.zeros((240, 320, 3), np.uint8)
    image[150:] = (120, 110, 90)  # floor
    image[:150] = (30, 60, 160)  # a blue patch beyond it
    scan = ranger.scan(image)
    assert set(scan.status) == {"boundary"} and ranger.last_scan is scan
    samples = ranger.boundary_samples()
    assert samples.shape == (16, 4) and samples.dtype == np.uint32
    # min_run_px (3) rows of each boundary's run are kept; their colour part is the blue's
    # bin, written out here from docs/appearance-ranger.md (intensity x two chroma axes)
    r, g, b = 30, 60, 160
    chroma = lambda c: (min(max(c + 96, 0), 16 * 12 - 1)) >> 4  # noqa: E731
    blue = (((r + g + b) // 3 >> 4) * 12 + chroma(r - g)) * 12 + chroma((r + g) // 2 - b)
    assert (samples[:, :3] // 8 == blue).all() and (samples[:, 3] == NO_SAMPLE).all()
    # Refused whole: not packed samples; skipped: empty slots.
    for bad in (np.array([-1]), np.array([0.5]), np.array([2304 * 8], np.uint32)):
        with pytest.raises(fs.OptionError, match="samples"):
            ranger.learn_driven_floor(np.concatenate([samples.ravel(), bad]))
    assert ranger.learn_driven_floor(np.full(3, NO_SAMPLE, np.uint32)) == 0
    # not confirmed by this frame's reference band (floor, not blue): nothing learned
    assert ranger.learn_driven_floor(samples) == 0
    assert ranger.scan(image).status.tolist() == ["boundary"] * 16
    assert not ranger.driven_floor_columns.any()
    assert np.isnan(ranger.driven_floor_borders).all()
    # driven over: the frame taken there shows the blue in its reference band
    on_it = np.full_like(image, (30, 60, 160))
    ranger.scan(on_it)
    assert 24 < ranger.learn_driven_floor(samples) <= 48
    assert set(ranger.scan(image).status) == {"no_boundary"}
    assert ranger.driven_floor_columns.all()
    # the border between the floor and the blue driven over (rows 150 / 149), within a row:
    # the blue's lowest row has the step down to the floor in its texture
    np.testing.assert_allclose(ranger.driven_floor_borders, 149.5, atol=1.0)
    ranger.reset_model()
    assert set(ranger.scan(image).status) == {"boundary"}
