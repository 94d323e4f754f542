"""The avoidance map's insertions in the Rust core against the numpy/OpenCV implementation they
replaced (tests/avoidance_map_reference.py): the same log odds, bit for bit, on the ranger's
scans of simulated corridor and room views, on random scans with every column status, odd
geometry and windows the fan leaves, and on laser scans."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from avoidance_map_reference import ReferenceAvoidanceMap
from floorscan.drive import AvoidanceMap, AvoidanceMapOptions
from floorscan.drive.loop import make_table
from floorscan.drive.sensor_model import VisualSensorModel
from floorscan.errors import FloorscanError
from floorscan.ranging.ranger import VisualRanger
from floorscan.sim import Camera, World, render_image


def _pair(center=(0.0, 0.0), **options):
    o = AvoidanceMapOptions(**options)
    return AvoidanceMap(o, center=center), ReferenceAvoidanceMap(o, center=center)


def _same(a, b):
    assert a.log_odds.dtype == b.log_odds.dtype == np.float32
    diff = np.count_nonzero(a.log_odds != b.log_odds)
    assert diff == 0, f"{diff} cells differ; max {np.abs(a.log_odds - b.log_odds).max()}"
    # the confirmed obstacles (a flag left on a cell no longer positive is never read)
    held = a.log_odds > 0
    np.testing.assert_array_equal(a.confirmed[held], b.confirmed[held])
    # the planner's layers likewise
    diff = np.count_nonzero(a.plan_log_odds != b.plan_log_odds)
    assert diff == 0, f"{diff} planner's cells differ"
    held = a.plan_log_odds > 0
    np.testing.assert_array_equal(a.plan_confirmed[held], b.plan_confirmed[held])
    np.testing.assert_array_equal(a.plan_near_hits, b.plan_near_hits)


@pytest.mark.parametrize("world_name", ["corridor", "room"])
def test_ranger_scans_along_a_tour_give_the_same_map(world_name):
    world, cam = World.builtin(world_name), Camera(width=320, height=240)
    table = make_table(cam, "exact")
    ranger = VisualRanger(table, columns=160)
    ours, ref = _pair(center=world.start[:2])
    tour = np.asarray(world.tour, np.float64)
    x, y, yaw = world.start
    for k in range(12):
        gx, gy = tour[k % len(tour)]
        yaw = math.atan2(gy - y, gx - x) + (0.3 if k % 3 == 1 else 0.0)
        x, y = x + 0.25 * math.cos(yaw), y + 0.25 * math.sin(yaw)
        pose = (x, y, yaw)
        scan = ranger.scan(render_image(world, cam, pose, seed=0, frame=k))
        for m in (ours, ref):
            m.decay(0.1)
            m.recenter(x, y)
            m.insert_visual(scan, pose, mount=cam.robot_from_camera, table=table)
        _same(ours, ref)
    assert np.count_nonzero(ours.log_odds) > 500


def _random_scan(rng, n):
    a = np.sort(rng.uniform(-1.2, 1.2, n))
    r = rng.uniform(0.2, 6.0, n) * (1 + 0.3 * np.sin(5 * a))
    near = rng.uniform(0.2, 0.5, n)
    status = rng.choice(4, n, p=[0.6, 0.2, 0.1, 0.1]).astype(np.uint8)
    x, y = r * np.cos(a), r * np.sin(a)
    nx, ny = near * np.cos(a), near * np.sin(a)
    fp = rng.uniform(0.0, 0.08, n)
    fp[rng.uniform(size=n) < 0.1] = np.nan
    bad = rng.uniform(size=n) < 0.05
    x[bad] = np.nan
    nx[rng.uniform(size=n) < 0.03] = np.inf
    # some boundaries nearer than their near edge, some at the camera
    x[rng.uniform(size=n) < 0.03] = 0.0
    return SimpleNamespace(
        status_codes=status,
        x=x,
        y=y,
        near_x=nx,
        near_y=ny,
        footprints=fp,
        columns=np.arange(n, dtype=np.uint32),
        rows=np.zeros(n),
    )


class _Table:
    """Predicted errors: NaN for some columns."""

    def lookup_error(self, u, v):
        e = 0.005 + 0.002 * (np.asarray(u) % 7)
        e[np.asarray(u) % 11 == 0] = np.nan
        return e


@pytest.mark.parametrize(
    "clearing, confirmed, confirm_range, confirmed_clearing, persist_range",
    [
        (0.0, 0.0, 0.5, 1.0, 0.0),
        (0.4, 1.0, 0.0, 0.25, 0.5),
        (1.0, 0.0, 0.5, 0.25, 2.0),
        (0.0, 0.0, 2.0, 1.0, 0.5),
        (0.0, 0.0, 0.3, 0.25, 6.0),
    ],
)
def test_random_scans_with_every_status_give_the_same_map(
    clearing, confirmed, confirm_range, confirmed_clearing, persist_range
):
    rng = np.random.default_rng(3)
    model = VisualSensorModel(
        fusion_weight=0.9,
        margin_sigmas=1.5,
        hit_b=-0.3,
        no_boundary_clearing=clearing,
        confirmed_nats=confirmed,
        confirm_range_m=confirm_range,
        confirmed_clearing=confirmed_clearing,
        persist_range_m=persist_range,
    )
    for trial in range(30):
        cell = [0.05, 0.04, 0.1][trial % 3]
        ours, ref = _pair(center=(1.0, -2.0), size_m=6.0, cell_size_m=cell, clamp_nats=(-1.5, 2.5))
        for k in range(3):
            scan = _random_scan(rng, int(rng.integers(2, 200)))
            # poses near the window's edge: fans run off it
            pose = (1.0 + rng.uniform(-3, 3), -2.0 + rng.uniform(-3, 3), rng.uniform(-4, 4))
            mount = (0.1, 0.02, rng.uniform(-0.2, 0.2))
            table = _Table() if k % 2 else None
            for m in (ours, ref):
                with np.errstate(all="ignore"):  # inf - inf in the reference's sums
                    m.insert_visual(scan, pose, mount=mount, table=table, model=model)
                m.decay(0.3)
            _same(ours, ref)


def test_laser_scans_give_the_same_map():
    rng = np.random.default_rng(5)
    ours, ref = _pair(center=(0.0, 0.0), probability_scale=1.0, probability_offset=0.0)
    angles = np.linspace(-3 * np.pi / 4, 3 * np.pi / 4, 271)
    for _ in range(10):
        r = rng.uniform(0.1, 6.0, angles.size)
        r[rng.uniform(size=r.size) < 0.2] = np.inf
        pose = (rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-3, 3))
        for m in (ours, ref):
            m.decay(0.1)
            m.insert_laser(r, angles, pose, range_max_m=4.0)
        _same(ours, ref)


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"probability_knots": None, "probability_scale": 0.7, "probability_offset": -0.4},
        {"bump_half_life_s": None, "half_life_s": 1.0, "cell_size_m": 0.04},
    ],
)
def test_scrolling_bumps_and_views_equal_the_reference(options):
    """Bumps, forgetting, scrolling and the planner's and the map's views (classes, known,
    occupied, calibrated probabilities) of random scans along a wandering path: the same as
    the numpy map's, cell for cell."""
    rng = np.random.default_rng(8)
    ours, ref = _pair(center=(0.5, 0.5), size_m=4.0, **options)
    pose = (0.5, 0.5, 0.0)
    for k in range(25):
        pose = (pose[0] + rng.normal(0, 0.4), pose[1] + rng.normal(0, 0.4), rng.uniform(-4, 4))
        scan = _random_scan(rng, int(rng.integers(20, 120)))
        bearing = rng.uniform(-1, 1)
        for m in (ours, ref):
            m.decay(0.2)
            m.recenter(pose[0], pose[1])
            with np.errstate(all="ignore"):
                m.insert_visual(scan, pose, mount=(0.1, 0.0, 0.0))
            if k % 4 == 0:
                m.mark_bump(pose, bearing, 0.2)
        assert (ours.x_cell, ours.y_cell) == (ref.x_cell, ref.y_cell)
        _same(ours, ref)
        np.testing.assert_array_equal(ours.bumps, ref.bumps)
        np.testing.assert_array_equal(ours.occupancy_classes(), ref.occupancy_classes())
        np.testing.assert_array_equal(ours.known(), ref.known())
        np.testing.assert_array_equal(ours.occupied(), ref.occupied())
        np.testing.assert_allclose(ours.probabilities(), ref.probabilities(), rtol=1e-12)
    assert ours.bumps.any() and ours.occupied().any() and (ours.occupancy_classes() == 0).any()


def test_bad_layers_and_readings_are_errors():
    m = AvoidanceMap()
    scan = _random_scan(np.random.default_rng(0), 20)
    scan.near_x = scan.near_x[:5]
    with pytest.raises(FloorscanError):
        m.insert_visual(scan, (0.0, 0.0, 0.0))
    with pytest.raises(FloorscanError):  # a layer of another shape
        m.log_odds = np.zeros((3, 3), np.float32)
    with pytest.raises(FloorscanError):  # not contiguous
        m._native.log_odds = np.zeros((m.n, 2 * m.n), np.float32)[:, ::2]
    with pytest.raises(FloorscanError):
        m.recenter(math.nan, 0.0)
    with pytest.raises(FloorscanError):
        m.insert_laser(np.ones(3), np.zeros(2), (0.0, 0.0, 0.0), range_max_m=4.0)
    with pytest.raises(FloorscanError):
        m.mark_bump((0.0, math.inf, 0.0), 0.0, 0.2)
    assert not m.log_odds.any()  # nothing was inserted by the refused calls


def _fan_scan(range_m, status, n=41):
    """Columns fanned over +-0.6 rad, all at ``range_m`` with ``status``, near edges at 0.3 m."""
    a = np.linspace(-0.6, 0.6, n)
    r = range_m / np.cos(a)  # a straight face across the view
    return SimpleNamespace(
        status_codes=np.full(n, status, np.uint8),
        x=r * np.cos(a),
        y=r * np.sin(a),
        near_x=0.3 * np.ones(n),
        near_y=0.3 * np.tan(a),
        footprints=np.full(n, 0.01),
        columns=np.arange(n, dtype=np.uint32),
        rows=np.zeros(n),
    )


@pytest.mark.parametrize("clearing", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("confirm_range", [0.5, 2.0])
@pytest.mark.parametrize("confirmed_clearing", [1.0, 0.25])
def test_columns_without_a_boundary_clear_a_mapped_face_only_by_their_share(
    clearing, confirm_range, confirmed_clearing
):
    """A face mapped from 1.5 m, then seen by columns that find no boundary (3 m out): its
    cells lose `no_boundary_clearing` x the free evidence, unless the face was nearer than
    `confirm_range_m` (then in full, as a fleck near the robot); columns that find the
    floor's end farther on (a boundary at 3 m) clear a confirmed face in the planner's layer
    by `confirmed_clearing` x the free evidence (so do no-boundary columns when
    `no_boundary_clearing` is 1: none of their floor is set apart), an unconfirmed one in
    full; the map's own layer takes the same evidence with a `confirmed_clearing` of 1."""
    model = VisualSensorModel(
        no_boundary_clearing=clearing,
        confirm_range_m=confirm_range,
        confirmed_clearing=confirmed_clearing,
    )
    face = (1.0 + 1.5 + 0.025, 0.0)  # a cell centre on the face, camera at x = 1
    confirmed = confirm_range <= 1.5

    def shares(full_share):
        weak_share = clearing if clearing < 1.0 else full_share
        return [(1, weak_share if confirmed else 1.0), (0, full_share if confirmed else 1.0)]

    for (later, share), (_, plan_share) in zip(shares(1.0), shares(confirmed_clearing)):
        m = AvoidanceMap(AvoidanceMapOptions(half_life_s=None), center=(2.0, 0.0))
        pose = (1.0, 0.0, 0.0)
        m.insert_visual(_fan_scan(1.5, 0), pose, model=model)
        i, j = (int(c) for c in m.to_cells(*face))
        before = float(m.log_odds[j, i])
        assert before > 0.5 and float(m.plan_log_odds[j, i]) == before
        m.insert_visual(_fan_scan(3.0, later), pose, model=model)
        # the free evidence at the cell's range, as the model gives it
        r = math.hypot((i + 0.5) * m.cell + m.origin_m[0] - 1.0, (j + 0.5) * m.cell + m.origin_m[1])
        free = np.float32(model.fusion_weight) * np.float32(model.free_logit(np.float32(r)))
        expected = np.clip(before + share * free, *m.options.clamp_nats)
        assert float(m.log_odds[j, i]) == pytest.approx(float(expected), abs=1e-4)
        expected = np.clip(before + plan_share * free, *m.options.clamp_nats)
        assert float(m.plan_log_odds[j, i]) == pytest.approx(float(expected), abs=1e-4)
    # unknown floor before the face takes any column's free evidence in full
    m = AvoidanceMap(AvoidanceMapOptions(half_life_s=None), center=(2.0, 0.0))
    m.insert_visual(_fan_scan(3.0, 1), (1.0, 0.0, 0.0), model=model)
    i, j = (int(c) for c in m.to_cells(*face))
    assert float(m.log_odds[j, i]) < -1.0


def test_no_boundary_clearing_is_validated():
    with pytest.raises(FloorscanError, match="no_boundary_clearing"):
        VisualSensorModel(no_boundary_clearing=1.5)
    with pytest.raises(FloorscanError, match="confirmed_nats"):
        VisualSensorModel(confirmed_nats=-0.5)
    with pytest.raises(FloorscanError, match="confirmed_nats"):
        VisualSensorModel(confirmed_nats=float("nan"))
    with pytest.raises(FloorscanError, match="confirm_range_m"):
        VisualSensorModel(confirm_range_m=-0.1)
    with pytest.raises(FloorscanError, match="confirm_range_m"):
        VisualSensorModel(confirm_range_m=float("inf"))
    for bad in (0.0, -0.2, 1.5, float("nan")):
        with pytest.raises(FloorscanError, match="confirmed_clearing"):
            VisualSensorModel(confirmed_clearing=bad)
