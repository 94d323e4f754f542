"""floorscan.OccupancyGrid: update rules on hand-worked tiny grids, arrays, images, queries and
errors (bad input raises and leaves the map unchanged)."""

import math

import floorscan
import numpy as np
import pytest
from floorscan import (
    GeometryError,
    LengthMismatchError,
    OccupancyGrid,
    OptionError,
    OutOfBoundsError,
    Scan,
)

HIT, MISS = 850, -400


def unit_grid(**kw):
    return OccupancyGrid(cell_size_m=1.0, **kw)


def row(grid, y, n):
    e = floorscan.GridExtent(0, y, n, 1, grid.cell_size_m, (0.0, float(y)))
    return grid.raw(e)[0].tolist()


def scan(points, near, status="boundary"):
    n = len(points)
    pts = np.asarray(points, dtype=float)
    nears = np.asarray(near, dtype=float)
    return Scan.from_arrays(
        timestamp=0.0,
        columns=np.arange(n),
        rows=np.full(n, 100.0),
        status=[status] * n if isinstance(status, str) else status,
        x=pts[:, 0],
        y=pts[:, 1],
        near_x=nears[:, 0],
        near_y=nears[:, 1],
    )


ROBOT = (0.5, 0.5, 0.0)


def test_boundary_marks_free_space_starts_at_the_near_edge_and_beyond_is_untouched():
    g = unit_grid()
    g.insert_scan(scan([(4.0, 0.0)], [(2.0, 0.0)]), ROBOT)
    assert row(g, 0, 7) == [0, 0, MISS, MISS, HIT, 0, 0]


def test_once_per_scan_and_occupied_wins():
    g = unit_grid()
    # Column A sees a boundary in cell 2; columns B and C look through cell 2 to cell 5.
    s = scan([(2.0, 0.0), (5.0, 0.0), (5.2, 0.1)], [(1.0, 0.0)] * 3)
    stats = g.insert_scan(s, ROBOT)
    assert row(g, 0, 7) == [0, MISS, HIT, MISS, MISS, HIT, 0]
    assert stats.rays == 3 and stats.cells_hit == 2


def test_no_boundary_too_close_and_invalid_columns():
    g = unit_grid()
    s = scan(
        [(3.0, 0.0), (np.nan, np.nan), (np.nan, np.nan)],
        [(1.0, 0.0), (2.0, 1.0), (2.0, 2.0)],
        status=["no_boundary", "too_close", "invalid"],
    )
    g.insert_scan(s, ROBOT)
    assert row(g, 0, 5) == [0, MISS, MISS, MISS, 0]
    assert row(g, 1, 4) == [0, 0, HIT, 0]
    assert row(g, 2, 4) == [0, 0, 0, 0]
    ignored = unit_grid(too_close="ignore")
    ignored.insert_scan(s, ROBOT)
    assert row(ignored, 1, 4) == [0, 0, 0, 0]


def test_mount_places_the_camera_on_the_robot():
    g = unit_grid()
    # Robot at (5.5, 5.5) facing +y; camera 1 m ahead of it, looking to the robot's left.
    g.insert_scan(
        scan([(2.0, 0.0)], [(1.0, 0.0)]), (5.5, 5.5, math.pi / 2), mount=(1.0, 0.0, math.pi / 2)
    )
    assert row(g, 6, 7) == [0, 0, 0, HIT, MISS, 0, 0]


def test_clamping_bounds_the_evidence():
    g = unit_grid()
    for _ in range(20):
        g.insert_laser([3.0], angles=[0.0], range_max_m=10.0, pose=ROBOT)
    assert row(g, 0, 5) == [-2000, -2000, -2000, 3500, 0]


def test_laser_max_range_clears_without_marking():
    g = unit_grid()
    g.insert_laser(
        [np.inf, 2.0], angle_min=0.0, angle_increment=math.pi, range_max_m=3.0, pose=(4.5, 0.5, 0.0)
    )
    # +inf to the right: cleared up to 3 m (cells 4..7); 2 m to the left: hit at cell 2.
    assert row(g, 0, 9) == [0, 0, HIT, MISS, MISS, MISS, MISS, MISS, 0]


def test_batch_insert_equals_one_by_one():
    rng = np.random.default_rng(1)
    ranges = rng.uniform(0.2, 4.0, size=(50, 32))
    ranges[rng.random(ranges.shape) < 0.1] = np.inf
    poses = np.column_stack(
        [rng.uniform(-2, 2, 50), rng.uniform(-2, 2, 50), rng.uniform(-3, 3, 50)]
    )
    kw = dict(angle_min=-1.5, angle_increment=0.1, range_max_m=3.5, mount=(0.1, 0.0, 0.05))
    a, b = OccupancyGrid(), OccupancyGrid()
    total = a.insert_lasers(ranges, poses=poses, **kw)
    for r, p in zip(ranges, poses):
        b.insert_laser(r, pose=p, **kw)
    assert a.extent == b.extent
    np.testing.assert_array_equal(a.raw(), b.raw())
    assert total.rays == 50 * 32 and total.cells_traversed > total.rays


def test_sonar_and_generic_rays():
    g = OccupancyGrid(cell_size_m=0.1)
    g.insert_sonar(2.0, pose=(0.05, 0.05, 0.0), beam_width_rad=0.4, range_max_m=5.0)
    arc = floorscan.GridExtent(20, 0, 1, 1, 0.1, (2.0, 0.0))
    assert g.raw(arc)[0, 0] == 400  # one sonar echo: weak evidence (p 0.6), not yet occupied
    assert not g.is_occupied(2.05, 0.05) and g.raw()[g.raw() < 0].max() == -200
    r = OccupancyGrid(cell_size_m=1.0)
    r.insert_rays([[0.5, 0.5]], [[3.5, 0.5]], hits=True, evidence=(1.0, -0.5))
    assert row(r, 0, 5) == [-500, -500, -500, 1000, 0]


def test_arrays_follow_nav_msgs_layout_and_values():
    g = OccupancyGrid(cell_size_m=0.5)
    g.insert_laser([1.0], angles=[math.pi / 2], range_max_m=5.0, pose=(0.25, 0.25, 0.0))
    e = g.extent
    assert (e.x_cell, e.y_cell, e.width, e.height) == (0, 0, 1, 3)
    assert e.origin_m == (0.0, 0.0) and e.bounds_m == ((0.0, 0.0), (0.5, 1.5))
    raw = g.raw()
    assert raw.dtype == np.int16 and raw.shape == (3, 1)
    assert raw[:, 0].tolist() == [MISS, MISS, HIT]  # row 0 is the lowest y
    np.testing.assert_allclose(g.log_odds()[:, 0], [-0.4, -0.4, 0.85], atol=1e-6)
    p = g.probabilities()
    np.testing.assert_allclose(p[:, 0], 1 / (1 + np.exp(-np.array([-0.4, -0.4, 0.85]))))
    msg = g.to_occupancy_msg(floorscan.GridExtent(0, 0, 2, 3, 0.5, (0.0, 0.0)))
    assert msg.dtype == np.int8 and msg.tolist() == [[40, -1], [40, -1], [70, -1]]
    assert g.occupancy_classes()[:, 0].tolist() == [1, 1, 2]
    data, resolution, origin = g.to_occupancy_grid()
    assert data.tolist() == [[40], [40], [70]] and resolution == 0.5 and origin == (0.0, 0.0, 0.0)


def test_images_have_the_paper_look(tmp_path):
    g = OccupancyGrid(cell_size_m=0.5)
    for _ in range(5):
        g.insert_laser([1.0], angles=[math.pi / 2], range_max_m=5.0, pose=(0.25, 0.25, 0.0))
    e = floorscan.GridExtent(0, 0, 2, 3, 0.5, (0.0, 0.0))
    img = g.to_image(extent=e)
    # Top row is the highest y: the obstacle; right column unknown.
    assert img[0, 0] < 40 and img[2, 0] > 200 and img[0, 1] in (127, 128)
    tri = g.to_image(style="trinary", extent=e)
    assert tri.tolist() == [[0, 205], [254, 205], [254, 205]]
    from PIL import Image

    path = g.to_png(tmp_path / "m.png", scale=3, extent=e)
    with Image.open(path) as im:
        assert im.size == (6, 9) and im.mode == "L"
        assert np.asarray(im)[0, 0] == img[0, 0]
    assert [p.name for p in tmp_path.iterdir()] == ["m.png"]
    with pytest.raises(OptionError, match="style"):
        g.to_image(style="fancy")
    # An empty growing map still exports: one unknown cell at the lattice origin.
    with Image.open(OccupancyGrid().to_png(tmp_path / "empty.png")) as im:
        assert im.size == (1, 1) and np.asarray(im)[0, 0] == 128


def test_queries_match_brute_force():
    g = OccupancyGrid(cell_size_m=0.1)
    rng = np.random.default_rng(3)
    origin = (0.05, 0.05, 0.0)
    ranges = rng.uniform(0.5, 2.0, size=64)
    for _ in range(4):  # 4 misses: p = 0.17, free
        g.insert_laser(
            ranges,
            angle_min=-math.pi,
            angle_increment=2 * math.pi / 64,
            range_max_m=3.0,
            pose=origin,
        )
    classes = g.occupancy_classes()
    e = g.extent
    iy, ix = np.nonzero(classes == 2)
    x0 = e.origin_m[0] + ix * 0.1
    y0 = e.origin_m[1] + iy * 0.1
    pts = rng.uniform(-2.5, 2.5, size=(200, 2))
    d = g.distance_to_nearest_occupied(pts[:, 0], pts[:, 1], max_distance_m=1.0)
    for (px, py), got in zip(pts, d):
        dx = np.maximum(np.maximum(x0 - px, px - (x0 + 0.1)), 0)
        dy = np.maximum(np.maximum(y0 - py, py - (y0 + 0.1)), 0)
        want = np.hypot(dx, dy).min()
        assert got == pytest.approx(want) if want <= 1.0 else got == math.inf
    # Free and occupied agree with the classes array, scalars give plain bools.
    fx, fy = (
        e.origin_m[0] + 0.05 + np.arange(e.width) * 0.1,
        e.origin_m[1] + 0.05 + np.arange(e.height) * 0.1,
    )
    X, Y = np.meshgrid(fx, fy)
    np.testing.assert_array_equal(g.is_free(X.ravel(), Y.ravel()), (classes == 0).ravel())
    np.testing.assert_array_equal(g.is_occupied(X.ravel(), Y.ravel()), (classes == 2).ravel())
    assert g.is_free(0.05, 0.05) is True and isinstance(
        g.distance_to_nearest_occupied(0.0, 0.0), float
    )


def test_bad_input_raises_and_leaves_the_map_unchanged():
    g = OccupancyGrid(cell_size_m=0.1)
    g.insert_laser([1.0, 2.0], angles=[0.0, 1.0], range_max_m=5.0, pose=(0, 0, 0))
    before = g.raw().copy()
    with pytest.raises(GeometryError):
        g.insert_laser([1.0, 2.0], angles=[0.0, 1.0], range_max_m=5.0, pose=(np.nan, 0, 0))
    with pytest.raises(GeometryError, match="beam 1"):
        g.insert_laser([1.0, np.nan], angles=[0.0, 1.0], range_max_m=5.0, pose=(0, 0, 0))
    with pytest.raises(GeometryError):
        g.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0, 0, 0), mount=(0, 0, np.inf))
    with pytest.raises(LengthMismatchError):
        g.insert_laser([1.0, 2.0], angles=[0.0], range_max_m=5.0, pose=(0, 0, 0))
    with pytest.raises(LengthMismatchError):
        g.insert_lasers(np.ones((3, 2)), poses=np.zeros((2, 3)), angles=[0.0, 1.0], range_max_m=5.0)
    bad = np.ones((3, 2))
    bad[2, 1] = np.nan
    with pytest.raises(GeometryError, match="scan 2"):
        g.insert_lasers(bad, poses=np.zeros((3, 3)), angles=[0.0, 1.0], range_max_m=5.0)
    with pytest.raises(LengthMismatchError):
        g.insert_sonar(
            [1.0, 2.0], pose=(0, 0, 0), beam_width_rad=0.3, range_max_m=4.0, mounts=np.zeros((3, 3))
        )
    with pytest.raises(GeometryError):
        g.insert_scan(scan([(4.0, 0.0)], [(2.0, 0.0)]), (0, 0, np.inf))
    with pytest.raises(TypeError):
        g.insert_scan("not a scan", (0, 0, 0))
    with pytest.raises(TypeError):
        g.insert_laser([1.0], range_max_m=5.0, pose=(0, 0, 0))  # no angles
    np.testing.assert_array_equal(g.raw(), before)


def test_fixed_bounds_clip_rays_and_refuse_poses_outside():
    g = OccupancyGrid(cell_size_m=1.0, bounds_m=((0.0, 0.0), (4.0, 2.0)))
    assert g.extent.shape == (2, 4)
    g.insert_laser([6.0], angles=[0.0], range_max_m=10.0, pose=(0.5, 0.5, 0.0))
    assert g.raw()[0].tolist() == [MISS] * 4
    before = g.raw().copy()
    with pytest.raises(OutOfBoundsError, match="outside"):
        g.insert_laser([1.0], angles=[0.0], range_max_m=10.0, pose=(4.5, 0.5, 0.0))
    np.testing.assert_array_equal(g.raw(), before)
    assert isinstance(OutOfBoundsError("x"), floorscan.FloorscanError)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(cell_size_m=0.0), "cell_size_m"),
        (dict(cell_size_m="big"), "cell_size_m"),
        (dict(bounds_m=((1, 1), (0, 0))), "bounds_m"),
        (dict(clamp_min_nats=1.0), "clamp_min_nats"),
        (dict(occupied_threshold=0.3), "occupied_threshold"),
        (dict(free_threshold=0.7), "free_threshold"),
        (dict(laser=(-1.0, -0.4)), "laser"),
        (dict(visual=(0.5,)), "visual"),
        (dict(sonar=(0.5, 0.2)), "sonar"),
        (dict(too_close="maybe"), "too_close"),
        (dict(ray_walk="bresenham"), "ray_walk"),
    ],
)
def test_options_are_validated_by_name(kwargs, name):
    with pytest.raises(OptionError, match=name):
        OccupancyGrid(**kwargs)


@pytest.mark.parametrize("angle", [0.1, 0.4636, 0.9, 2.5, -1.2, math.pi / 4])
def test_the_thin_walk_clears_one_cell_per_step_of_the_beam_s_crossings(angle):
    """`ray_walk = "thin"`: one cell per cell column (row, for a steep beam) from the start
    to the end, each a cell the exact walk also clears (so the beam truly crosses it)."""
    pose, r = (0.05, 0.05, 0.0), 2.973
    maps = {}
    for walk in ("exact", "thin"):
        g = OccupancyGrid(cell_size_m=0.1, ray_walk=walk)
        stats = g.insert_laser([r], angles=[angle], range_max_m=5.0, pose=pose)
        maps[walk] = (g, stats)
    (exact, _), (thin, stats) = maps["exact"], maps["thin"]
    ex, ey = pose[0] + r * math.cos(angle), pose[1] + r * math.sin(angle)
    di, dj = abs(math.floor(ex / 0.1)), abs(math.floor(ey / 0.1))
    assert min(abs(v / 0.1 - round(v / 0.1)) for v in (ex, ey)) > 1e-3  # no end on a line
    assert stats.cells_traversed in (max(di, dj) + 1, max(di, dj) + 2)
    extent = exact.extent  # rows from y's lowest cell up, as nav_msgs
    exact_l, thin_l = exact.log_odds(extent), thin.log_odds(extent)
    thin_free, exact_free = thin_l < 0, exact_l < 0
    assert not (thin_free & ~exact_free).any()  # a subset of the crossed cells
    # one per step along the major axis (the hit cell holds the last step)
    touched = thin_l != 0
    per_line = touched.sum(axis=0 if di >= dj else 1)
    per_line = per_line[per_line > 0]
    assert per_line.size == max(di, dj) + 1
    assert set(per_line.tolist()) <= {1, 2} and (per_line == 2).sum() <= 1
    # fewer cells, unless the beam runs through the cell corners (45 degrees from a centre)
    diagonal = abs(abs(math.tan(angle)) - 1) < 1e-9
    assert thin_free.sum() == exact_free.sum() if diagonal else thin_free.sum() < exact_free.sum()


def test_evidence_from_error_rates_and_copy():
    ev = floorscan.Evidence.from_error_rates(false_alarm=0.2, miss_rate=0.1)
    assert ev.hit_nats == pytest.approx(math.log(0.9 / 0.2)) and ev.miss_nats == pytest.approx(
        math.log(0.1 / 0.8)
    )
    g = OccupancyGrid(laser=ev)
    assert g.options["inserter"]["laser"]["hit_nats"] == pytest.approx(ev.hit_nats)
    g.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0, 0, 0))
    c = g.copy()
    c.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0, 0, 0))
    assert c.raw().max() > g.raw().max()
    assert g.memory_bytes >= g.allocated_tiles * 128 * 128 * 2 > 0
