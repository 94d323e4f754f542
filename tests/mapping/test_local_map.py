"""floorscan.LocalMap: a robot-centred window fed with pose changes, equal to a global map
built from the same data over the window (cells that never left it)."""

import math

import floorscan
import numpy as np
import pytest
from floorscan import GeometryError, LocalMap, OccupancyGrid, OptionError


def compose(a, b):
    x, y, t = a
    c, s = math.cos(t), math.sin(t)
    yaw = math.remainder(t + b[2], 2 * math.pi)
    return (x + c * b[0] - s * b[1], y + s * b[0] + c * b[1], yaw)


def test_local_map_equals_the_global_map_over_the_window():
    rng = np.random.default_rng(5)
    local, world = LocalMap(), OccupancyGrid()
    start = local.extent
    inside = np.ones(start.shape, bool)  # cells of the first window still never left
    pose = (0.0, 0.0, 0.0)
    kw = dict(angle_min=-math.pi, angle_increment=2 * math.pi / 120, range_max_m=2.5)
    for _ in range(60):
        delta = (rng.uniform(-0.03, 0.05), rng.uniform(-0.03, 0.03), rng.uniform(-0.2, 0.2))
        pose = compose(pose, delta)
        local.move_to(pose)
        w = local.extent
        xs = start.x_cell + np.arange(start.width)
        ys = start.y_cell + np.arange(start.height)
        inside &= ((ys[:, None] >= w.y_cell) & (ys[:, None] < w.y_cell + w.height)) & (
            (xs >= w.x_cell) & (xs < w.x_cell + w.width)
        )[None, :]
        ranges = rng.uniform(0.3, 3.0, size=120)
        local.insert_laser(ranges, **kw)
        world.insert_laser(ranges, pose=pose, **kw)
    assert local.pose == pytest.approx(pose)
    assert local.extent != start, "the window should have scrolled"
    ours, theirs = local.raw(start), world.raw(start)
    assert inside.sum() > 1500 and (theirs[inside] != 0).sum() > 1000
    np.testing.assert_array_equal(ours[inside], theirs[inside])


def test_move_by_integrates_increments_and_the_window_follows():
    local = LocalMap(size_m=1.0, cell_size_m=0.1)
    assert local.extent.shape == (10, 10) and local.extent.origin_m == pytest.approx((-0.5, -0.5))
    for _ in range(10):
        local.move_by((0.1, 0.0, math.pi / 20))
    expected = (0.0, 0.0, 0.0)
    for _ in range(10):
        expected = compose(expected, (0.1, 0.0, math.pi / 20))
    x, y, yaw = local.pose
    assert (x, y, yaw) == pytest.approx(expected) and yaw == pytest.approx(math.pi / 2)
    # Ten 0.1 m chords turning pi/20 after each: vertices of a regular polygon whose
    # circumscribed circle (radius 0.1 / (2 sin(pi/40))) passes through the start.
    r = 0.1 / (2 * math.sin(math.pi / 40))
    centre = (0.05, 0.05 / math.tan(math.pi / 40))
    assert math.hypot(x - centre[0], y - centre[1]) == pytest.approx(r)
    e = local.extent
    cx, cy = e.x_cell + 5, e.y_cell + 5
    assert (cx, cy) == (math.floor(x / 0.1), math.floor(y / 0.1))


def test_robot_view_rotates_with_the_robot():
    local = LocalMap(pose=(0.0, 0.0, math.pi / 2))
    local.insert_laser([1.0], angles=[0.0], range_max_m=3.0)
    view = local.robot_view(kind="raw")
    assert view.shape == (96, 96)
    rows, cols = np.nonzero(view > 0)
    assert rows.tolist() == [47] and cols.tolist() == [73]  # 1 m straight ahead
    p = local.robot_view(width=20, height=10)
    assert p.shape == (10, 20) and p.dtype == np.float64 and np.all((p >= 0) & (p <= 1))
    # In the local frame the same obstacle is 1 m along +y.
    assert (
        local.raw()[np.nonzero(local.raw() > 0)].size == 1 and local.is_occupied(0.02, 1.02) is True
    )


def test_inserts_can_bring_the_pose():
    # As the run pipeline does: the odometry pose with every scan.
    a, b = LocalMap(), LocalMap()
    kw = dict(angles=[0.0, 1.0], range_max_m=3.0)
    a.insert_laser([1.0, 2.0], pose=(0.3, 0.1, 0.5), **kw)
    b.move_to((0.3, 0.1, 0.5))
    b.insert_laser([1.0, 2.0], **kw)
    assert a.pose == b.pose == (0.3, 0.1, 0.5)
    np.testing.assert_array_equal(a.raw(), b.raw())
    a.insert_sonar(1.0, beam_width_rad=0.3, range_max_m=2.0, pose=(0.0, 0.0, 0.0))
    assert a.pose == (0.0, 0.0, 0.0)
    assert LocalMap(too_close="mark_near_edge").options is not None


def test_local_map_errors():
    local = LocalMap()
    with pytest.raises(GeometryError):
        local.move_by((np.nan, 0.0, 0.0))
    with pytest.raises(GeometryError):
        local.move_to((0.0, np.inf, 0.0))
    assert local.pose == (0.0, 0.0, 0.0)
    with pytest.raises(OptionError, match="size_m"):
        LocalMap(size_m=0.01)
    with pytest.raises(OptionError, match="kind"):
        local.robot_view(kind="colour")
    assert isinstance(repr(local), str) and local.options["size_m"] == 3.84
    local.insert_sonar(
        [1.0, 1.5], beam_width_rad=0.4, range_max_m=3.0, mounts=[[0, 0, 0], [0, 0, math.pi]]
    )
    assert (local.raw() > 0).any() and floorscan.LocalMap is LocalMap


def _view():
    """One view: five columns to boundaries 1-2 m ahead, the floor seen from 0.3 m."""
    from floorscan import Scan

    xs = np.array([1.0, 1.3, 1.6, 1.9, 1.5])
    ys = np.array([-0.4, -0.2, 0.0, 0.2, 0.4])
    n = xs.size
    return Scan.from_arrays(
        timestamp=0.0,
        columns=np.arange(n),
        rows=np.full(n, 100.0),
        status=["boundary"] * n,
        x=xs,
        y=ys,
        near_x=np.full(n, 0.3),
        near_y=ys * 0.3 / xs,
    )


@pytest.mark.parametrize(
    "options, frames_to_free",
    [({}, 2), ({"visual": (0.85, -0.4)}, 4), ({"visual": (0.85, -1.5)}, 1)],
    ids=["default", "global-evidence", "strong-miss"],
)
def test_the_local_map_s_visual_evidence_sets_how_fast_a_view_settles(options, frames_to_free):
    """The local map's visual evidence is its own (``visual``): the default clears a view's
    floor in two frames (2 x 0.75 nats past the free threshold's 1.41); the global map's
    -0.4 needs four, a -1.5 one."""
    local = LocalMap(cell_size_m=0.1, **options)
    world = OccupancyGrid(cell_size_m=0.1)  # the global map's default evidence
    view = _view()
    for frame in range(1, 5):
        local.insert_scan(view)
        world.insert_scan(view, (0.0, 0.0, 0.0))
        seen = local.log_odds() != 0
        settled = (local.occupancy_classes() != 1)[seen]  # free (0) or occupied (2)
        assert seen.sum() > 40 and local.is_occupied(1.6, 0.0)
        assert settled.all() == (frame >= frames_to_free), frame
        # the global map's -0.4: free after 4 frames, not 3
        assert (world.occupancy_classes() == 0).any() == (frame >= 4), frame
    assert (
        LocalMap(**options).options["visual"]["miss_nats"]
        == {
            1: -1.5,
            2: -0.75,
            4: -0.4,
        }[frames_to_free]
    )
