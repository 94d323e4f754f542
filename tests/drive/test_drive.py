"""floorscan.drive: contact geometry against analytic distances, the ideal laser against
analytic ranges, the closed loop against the simulator's truth on a world written here (not
one the defaults were chosen on), the forgetting of a removed obstacle, options, the CLI."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from floorscan import OptionError
from floorscan.drive import (
    AvoidanceMap,
    AvoidanceMapOptions,
    DriveOptions,
    Solids,
    VisualSensorModel,
    drive,
    make_table,
)
from floorscan.drive.loop import with_drive_tables
from floorscan.errors import ConfigError
from floorscan.pipeline.config import Config
from floorscan.ranging.parallax import ParallaxRanger
from floorscan.ranging.ranger import VisualRanger
from floorscan.sim import Camera, World, render

HALL = """
name = "test hall"
seed = 7
tour = [[5.2, 1.5]]
[start]
x = 0.6
y = 1.5
yaw = 0.0
[coverings.carpet]
kind = "carpet"
brightness = 0.33
contrast = 0.07
[lighting]
ambient = 0.5
grid = { spacing_m = 2.0, power = 0.7 }
[[walls]]
from = [0.0, 0.0]
to = [6.0, 0.0]
[[walls]]
from = [6.0, 0.0]
to = [6.0, 3.0]
[[walls]]
from = [6.0, 3.0]
to = [0.0, 3.0]
[[walls]]
from = [0.0, 3.0]
to = [0.0, 0.0]
"""

BOX = """
[[boxes]]
center = [2.8, 1.5]
size = [0.45, 0.45]
height_m = 0.6
appearance = "metal"
"""


def test_clearance_is_the_distance_to_a_wall_face():
    wall = [[1.0, -2.0], [1.1, -2.0], [1.1, 2.0], [1.0, 2.0]]
    s = Solids.of_polygons([wall])
    assert s.clearance(0.5, 0.0) == pytest.approx(0.5)
    assert s.clearance(0.5, 2.3) == pytest.approx(math.hypot(0.5, 0.3))
    assert s.clearance(1.05, 0.0) == 0.0  # inside
    assert Solids.of_polygons([]).clearance(0, 0) == math.inf


def test_ideal_laser_ranges_match_analytic_geometry():
    wall = [[1.0, -5.0], [1.1, -5.0], [1.1, 5.0], [1.0, 5.0]]
    s = Solids.of_polygons([wall])
    angles = np.array([0.0, 0.5, -0.5, math.pi])
    r = s.laser((0.0, 0.0, 0.0), angles, range_max_m=4.0)
    assert r[0] == pytest.approx(1.0)
    assert r[1] == pytest.approx(1.0 / math.cos(0.5))
    assert r[2] == pytest.approx(1.0 / math.cos(0.5))
    assert r[3] == math.inf  # REP 117: no return
    r = s.laser((0.0, 0.0, 0.3), np.array([0.0]), range_max_m=4.0)
    assert r[0] == pytest.approx(1.0 / math.cos(0.3))


def test_world_solids_leave_out_table_tops_above_the_robot():
    w = World.from_toml(HALL + "\n[[tables]]\ncenter = [3.0, 1.5]\nsize = [1.0, 0.6]\n")
    s = Solids.of_world(w)
    # under the top, between the legs (inset 5 cm, 5 cm wide): 0.2 m to the nearest leg side
    assert s.clearance(3.0, 1.5) == pytest.approx(math.hypot(0.5 - 0.1, 0.3 - 0.1), abs=1e-6)


@pytest.mark.parametrize("sensor", ["laser", "camera"])
def test_the_robot_steers_around_a_box_on_the_route(sensor):
    world = World.from_toml(HALL + BOX)
    truth = Solids.of_world(world)
    result = drive(world, DriveOptions(seconds=40, table="exact", sensor=sensor, keep_frames=0))
    s = result.summary()
    assert s["collisions"] == 0
    assert s["waypoints_reached"] == 1
    poses = np.asarray(result.record.poses)
    # the robot passed the box (beyond its far face) without its footprint touching it
    assert poses[:, 0].max() > 3.1
    clear = [truth.clearance(x, y) for x, y, _ in poses]
    assert min(clear) > result.options.costmap.robot_radius_m
    assert s["min_clearance_m"] == pytest.approx(min(clear) - 0.18, abs=1e-4)
    # it went around, not through: somewhere beside the box it was off the straight line
    beside = np.abs(poses[:, 0] - 2.8) < 0.1
    assert np.abs(poses[beside, 1] - 1.5).min() > 0.2 + 0.18


def test_scan_matching_keeps_the_pose_estimate_on_the_true_pose():
    """The corridor's first four waypoints with the ideal laser: with scan matching the
    robot's pose estimate stays within 25 cm of the simulator's truth and every waypoint is
    reached; on odometry alone the same drive drifts past that bound."""
    world = World.builtin("corridor")
    tour = world.tour[:4]
    runs = {}
    for on in (True, False):
        o = DriveOptions(seconds=60, table="exact", sensor="laser", keep_frames=0, scan_matching=on)
        runs[on] = drive(world, o, waypoints=tour).summary()
    assert runs[True]["pose_error_m_max"] < 0.25
    assert runs[True]["waypoints_reached"] == 4
    assert runs[False]["pose_error_m_max"] > 0.25


def test_the_robot_stops_before_a_wall_across_the_route():
    world = World.from_toml(HALL + "\n[[boxes]]\nrect = [2.5, 0.0, 2.6, 3.0]\nheight_m = 1.0\n")
    result = drive(
        world,
        DriveOptions(
            seconds=25, table="exact", sensor="camera", keep_frames=0, waypoint_timeout_s=10
        ),
    )
    s = result.summary()
    assert s["collisions"] == 0
    assert s["waypoints_reached"] == 0
    poses = np.asarray(result.record.poses)
    assert poses[:, 0].max() < 2.5 - 0.18


def test_summary_fields_agree_with_the_record():
    world = World.from_toml(HALL)
    r = drive(world, DriveOptions(seconds=10, sensor="laser", keep_frames=0))
    s = r.summary()
    for key in (
        "collisions",
        "distance_m",
        "waypoints_reached",
        "waypoints_total",
        "min_clearance_m",
        "mean_speed_m_s",
    ):
        assert key in s
    poses = np.asarray(r.record.poses)
    d = np.hypot(*np.diff(poses[:, :2], axis=0).T).sum()
    assert s["distance_m"] == pytest.approx(d, abs=1e-3)
    assert s["mean_speed_m_s"] == pytest.approx(d / s["duration_s"], abs=1e-3)
    assert s["mean_speed_m_s"] <= 0.3 + 1e-9
    assert s["waypoints_total"] == 1


@pytest.mark.parametrize(
    "far_wall_x, clearing, confirmed_clearing, clears_by_sight",
    [
        # the floor's end in view beyond the box: boundary columns clear it, over several
        # frames (a confirmed obstacle's cell takes a share of their free evidence) ...
        (3.4, 0.0, 0.25, True),
        (3.4, 0.0, 1.0, True),  # ... or at once, as the model was
        (6.0, 0.0, 0.25, False),  # no boundary beyond (5.2 m off): only forgetting clears it
        (6.0, 1.0, 1.0, True),  # the model as it was: columns without a boundary clear it too
    ],
)
def test_a_removed_obstacle_clears_from_the_avoidance_map(
    far_wall_x, clearing, confirmed_clearing, clears_by_sight
):
    camera = Camera()
    table = make_table(camera, "exact")
    ranger = VisualRanger(table, columns=160)
    model = VisualSensorModel(no_boundary_clearing=clearing, confirmed_clearing=confirmed_clearing)
    pose = (0.8, 1.5, 0.0)
    hall = HALL.replace("6.0", str(far_wall_x))
    with_box, without = World.from_toml(hall + BOX), World.from_toml(hall)
    m = AvoidanceMap(center=pose[:2])
    box_x, box_y = m.to_cells(np.array([2.57, 2.57]), np.array([1.45, 1.55]))
    cells = (box_y.astype(int), box_x.astype(int))  # the box's near face (x = 2.575)

    def see(world, k, dt=0.1):
        m.decay(dt)
        image, _ = render(world, camera, pose, frame=k)
        scan = ranger.scan(image)
        m.insert_visual(scan, pose, mount=camera.robot_from_camera, table=table, model=model)

    for k in range(3):
        see(with_box, k)
    assert m.occupancy_classes()[cells].tolist() == [2, 2]
    frames = None
    factor = np.float32(0.5 ** (0.1 / m.options.half_life_s))
    # the most free evidence one frame gives a cell: the model's at range 0 (free_b > 0)
    most_free = model.fusion_weight * abs(model.free_a)
    map_frames = None  # the map's own evidence (its probabilities) clears in full
    free_nats = math.log(m.options.free_threshold / (1 - m.options.free_threshold))
    for k in range(10):
        before = m.plan_log_odds[cells] * factor
        see(without, 10 + k)
        # while believed occupied, a confirmed cell of the planner's layer loses at most its
        # share of that a frame
        believed = before > 0
        drop = (before - m.plan_log_odds[cells])[believed]
        assert (drop <= confirmed_clearing * most_free + 1e-5).all(), drop
        if map_frames is None and (m.log_odds[cells] < free_nats).all():
            map_frames = k + 1
        if (m.occupancy_classes()[cells] == 0).all():
            frames = k + 1
            break
    if clears_by_sight:
        assert frames is not None and map_frames is not None and map_frames <= 3
        if confirmed_clearing == 1.0:
            assert frames <= 3
        else:  # a saturated cell needs more frames than its share allows in three
            assert frames > 3
        return
    assert frames is None  # seen for 1 s, never cleared by the columns without a boundary
    # those columns add nothing to the cells believed occupied: their evidence only fades,
    # halving every half_life_s (3 s), and stops reading occupied once below logit(0.65)
    # no boundary beyond the box: both layers hold the same evidence there
    np.testing.assert_array_equal(m.log_odds[cells], m.plan_log_odds[cells])
    before = m.log_odds[cells].copy()
    assert (before > 0).all()
    expect = before.copy()
    occupied_nats = math.log(m.options.occupied_threshold / (1 - m.options.occupied_threshold))
    for k in range(100):
        see(without, 20 + k)
        expect = expect * factor
        np.testing.assert_allclose(m.log_odds[cells], expect, rtol=1e-5)
        classes = m.occupancy_classes()[cells]
        assert ((classes == 2) == (expect >= occupied_nats)).all()
    assert (m.occupancy_classes()[cells] != 2).all()  # 10 s of forgetting


def test_options_are_validated():
    with pytest.raises(OptionError):
        DriveOptions(speed_m_s=0.0)
    with pytest.raises(OptionError):
        DriveOptions(sensor="sonar")
    with pytest.raises(OptionError):
        DriveOptions(table="guess")
    with pytest.raises(OptionError, match="ranger"):
        DriveOptions(ranger="sonar")
    with pytest.raises(OptionError, match="bump_backup_m"):
        DriveOptions(bump_backup_m=-0.1)
    with pytest.raises(OptionError, match="bump_face_half_length_m"):
        AvoidanceMapOptions(bump_face_half_length_m=2.0)
    with pytest.raises(OptionError, match="bump_half_life_s"):
        AvoidanceMapOptions(bump_half_life_s=0.0)


def test_the_drive_ranges_with_its_own_kind_and_the_configs_options(monkeypatch):
    """DriveOptions.ranger picks the range sensor (edge by default, whatever the
    configuration's default kind); a configuration gives its options."""
    import floorscan.drive.loop as loop
    from floorscan.ranging.fused import FusedRanger

    built = []
    real = loop.ranger_from_config

    def spy(table, cfg, **kw):
        r = real(table, cfg, **kw)
        built.append(r)
        return r

    monkeypatch.setattr(loop, "ranger_from_config", spy)
    world = World.from_toml(HALL + BOX)
    o = DriveOptions(seconds=0.2, table="exact", keep_frames=0)
    drive(world, o)
    assert isinstance(built[-1], VisualRanger)
    cfg = Config().with_overrides({"ranger.threshold": 13.0})
    drive(
        world, DriveOptions(seconds=0.2, table="exact", keep_frames=0, ranger="fused"), config=cfg
    )
    assert isinstance(built[-1], FusedRanger)
    assert built[-1].edge.options["threshold"] == 13.0


def test_the_configs_parallax_checks_the_drives_edge_boundaries(monkeypatch):
    seen = []
    real = ParallaxRanger.scan

    def spy(self, image, *, timestamp=0.0, world_from_camera=None):
        scan = real(self, image, timestamp=timestamp, world_from_camera=world_from_camera)
        seen.append((world_from_camera, self.last_report["baseline_m"]))
        return scan

    monkeypatch.setattr(ParallaxRanger, "scan", spy)
    world = World.from_toml(HALL + BOX)
    cfg = Config().with_overrides({"parallax.enabled": True})
    drive(world, DriveOptions(seconds=3.0, table="exact", keep_frames=0), config=cfg)
    # every frame ranged through the cue with the camera's odometry pose; once the robot has
    # driven the least baseline, frames are compared
    assert len(seen) > 20 and all(p is not None for p, _ in seen)
    assert any(b >= cfg.parallax.min_baseline_m for _, b in seen)
    with pytest.raises(ConfigError, match="edge ranger"):
        drive(world, DriveOptions(seconds=0.2, table="exact", ranger="fused"), config=cfg)


def test_cli_drive_end_to_end(tmp_path):
    world = tmp_path / "hall.toml"
    world.write_text(HALL + BOX)
    out = tmp_path / "out"
    cmd = [
        sys.executable,
        "-m",
        "floorscan",
        "drive",
        "--world",
        str(world),
        "--seconds",
        "3",
        "--table",
        "exact",
        "-o",
        str(out),
    ]
    subprocess.run(cmd, check=True, capture_output=True)
    s = json.loads((out / "summary.json").read_text())
    assert s["collisions"] == 0 and s["waypoints_total"] == 1 and s["distance_m"] > 0.3
    for name in ("map.yaml", "map.pgm", "path.png", "drive.gif"):
        assert (out / name).stat().st_size > 0
    bad = subprocess.run(
        cmd[:-2] + ["--speed", "-1", "-o", str(tmp_path / "x")], capture_output=True, text=True
    )
    assert bad.returncode != 0 and "speed" in bad.stderr


def test_cli_drive_reads_the_rangers_config_and_refuses_bad_keys(tmp_path):
    world = tmp_path / "hall.toml"
    world.write_text(HALL + BOX)
    base = [sys.executable, "-m", "floorscan", "drive", "--world", str(world), "--seconds", "2"]
    base += ["--table", "exact", "--no-gif"]
    good = tmp_path / "good.toml"
    good.write_text("[ranger]\nthreshold = 12.0\nnoise_multiple = 0.0\n")
    out = tmp_path / "out"
    subprocess.run(base + ["--config", str(good), "-o", str(out)], check=True, capture_output=True)
    assert json.loads((out / "summary.json").read_text())["distance_m"] > 0.1
    bad = tmp_path / "bad.toml"
    bad.write_text("[ranger]\nthreshhold = 12.0\n")
    done = subprocess.run(
        base + ["--config", str(bad), "-o", str(tmp_path / "x")], capture_output=True, text=True
    )
    assert done.returncode != 0 and "threshhold" in done.stderr
    assert "Traceback" not in done.stderr
    two = subprocess.run(
        base + ["--world", "room", "-o", str(tmp_path / "y")], capture_output=True, text=True
    )
    assert two.returncode == 2 and "one --world" in two.stderr


def test_cli_drive_settings_come_from_flags_then_drive_run_then_the_core(tmp_path):
    """`floorscan drive`'s own settings: a flag given wins over the config's [drive.run],
    which wins over the core's defaults; a bad [drive.run] key names itself."""
    from floorscan.cli import build_parser
    from floorscan.commands.drive import RUN, settings
    from floorscan.options import defaults

    parse = build_parser().parse_args
    cfg = Config.from_toml('[drive.run]\nspeed_m_s = 0.5\nseconds = 7.0\nsensor = "laser"\n')
    assert cfg.drive.options()["run"]["speed_m_s"] == 0.5
    own = settings(parse(["drive", "--seconds", "3", "-o", "x"]), cfg)
    assert (own["speed_m_s"], own["seconds"], own["sensor"]) == (0.5, 3.0, "laser")
    plain = settings(parse(["drive", "--no-gif", "-o", "x"]), None)
    assert plain["keep_frames"] == 0
    assert {k: v for k, v in plain.items() if k != "keep_frames"} == {
        k: (tuple(v) if k == "mid_range_m" else v)
        for k, v in defaults("drive_run").items()
        if k != "keep_frames"
    }
    assert RUN == defaults("drive_run")
    with pytest.raises(ConfigError, match="drive.run"):
        Config.from_toml("[drive.run]\nsped = 1.0\n")
    world = tmp_path / "hall.toml"
    world.write_text(HALL + BOX)
    conf = tmp_path / "c.toml"
    conf.write_text('[drive.run]\nseconds = 1.5\ntable = "exact"\nkeep_frames = 0\n')
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "floorscan", "drive", "--world", str(world), "--no-gif"]
    subprocess.run(cmd + ["--config", str(conf), "-o", str(out)], check=True, capture_output=True)
    s = json.loads((out / "summary.json").read_text())
    assert s["duration_s"] <= 1.5 + 1e-9 and s["table"] == "exact"


def test_pose_composition_keeps_yaw_in_minus_pi_to_pi():
    from floorscan.drive.loop import _between, _compose, _inverse

    a, b = (1.0, 2.0, 3.0), (0.5, -0.25, 0.5)
    c = _compose(a, b)
    assert -math.pi <= c[2] < math.pi
    assert c[2] == pytest.approx(3.5 - 2 * math.pi)
    back = _between(a, c)  # a^-1 * (a * b) = b
    assert back == pytest.approx(b)
    assert -math.pi <= _inverse((0.0, 0.0, -3.5))[2] < math.pi


def test_the_bumper_segment_is_the_contacts_bearing_rounded_to_the_ring():
    from floorscan.drive.loop import BUMPER_SEGMENTS, bumper_segment

    width = 2 * math.pi / BUMPER_SEGMENTS
    rng = np.random.default_rng(2)
    for _ in range(200):
        x, y, yaw = rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-math.pi, math.pi)
        bearing = rng.uniform(-math.pi, math.pi)
        contact = (x + 0.2 * math.cos(yaw + bearing), y + 0.2 * math.sin(yaw + bearing))
        b = bumper_segment((x, y, yaw), contact)
        # a segment centre, within half a segment of the true bearing (mod 2 pi)
        assert abs(math.remainder(b / width, 1.0)) < 1e-9
        assert abs(math.remainder(b - bearing, 2 * math.pi)) <= width / 2 + 1e-9
    assert bumper_segment((0.0, 0.0, math.pi / 2), (0.0, 0.2)) == pytest.approx(0.0)
    assert bumper_segment((0.0, 0.0, 0.0), (0.0, 0.2)) == pytest.approx(math.pi / 2)


def test_a_bump_mark_outlasts_the_camera_and_forgets_after_its_half_life():
    m = AvoidanceMap(center=(0.0, 0.0))
    m.mark_bump((0.0, 0.0, 0.0), math.pi / 2, 0.21)
    occ = m.occupied()
    rows, cols = np.nonzero(occ)
    x = (cols + m.x_cell + 0.5) * m.cell
    y = (rows + m.y_cell + 0.5) * m.cell
    # a face square to +y at 0.21 m, 0.3 m long: the cells whose squares the line crosses
    assert np.all(np.abs(y - 0.21) <= m.cell / 2 + 1e-9)
    assert np.all(np.abs(x) <= 0.15 + m.cell / 2 + 1e-9)
    assert len(rows) >= int(0.3 / m.cell)
    # the camera's free evidence does not clear it
    log_odds = m.log_odds
    log_odds[occ] = -2.0
    m.log_odds = log_odds
    assert (m.occupied() == occ).all()
    hl = m.options.bump_half_life_s
    m.decay(0.9 * hl)
    assert (m.occupied() == occ).all()
    m.decay(0.2 * hl)
    assert not m.occupied().any()


def test_the_bumper_gets_a_blind_robot_past_a_box_its_sensor_cannot_see(monkeypatch):
    """The laser sees only the hall's walls, not the box on the route: the robot must feel
    the box with its bumper, remember where, and go around. The marks lie along the touched
    face (truth), and with a memory shorter than its tries it does not get past."""
    world = World.from_toml(HALL + BOX)
    walls = Solids.of_world(World.from_toml(HALL))
    laser = Solids.laser
    monkeypatch.setattr(Solids, "laser", lambda self, *a, **k: laser(walls, *a, **k))
    runs = {}
    for hl in (120.0, 0.5):
        o = DriveOptions(seconds=60, sensor="laser", keep_frames=0)
        o = replace(o, map=o.map.replace(bump_half_life_s=hl))
        runs[hl] = drive(world, o)
    s = runs[120.0].summary()
    assert 1 <= s["collisions"] <= 2
    assert s["waypoints_reached"] == 1
    rec, m = runs[120.0].record, runs[120.0].map
    # the first contact is head-on with the box's west face (x = 2.575, y in [1.275, 1.725])
    first = rec.contacts[0]
    assert first["x"] == pytest.approx(2.575 - 0.18, abs=0.01)
    # the marks, carried from the odometry frame into the world frame as they were at the
    # contact, lie on that face's line (within a cell and the bumper segment's 22.5 degrees
    # over the mark's half length) and span the face's width around the contact
    k = int(np.searchsorted(rec.times_s, first["time_s"]))
    tx, ty, tth = rec.poses[k]
    ox, oy, oth = rec.odometry[k]
    d = tth - oth
    rows, cols = np.nonzero(m.bumps > 0.5)
    mx, my = (cols + m.x_cell + 0.5) * m.cell - ox, (rows + m.y_cell + 0.5) * m.cell - oy
    wx = tx + math.cos(d) * mx - math.sin(d) * my
    wy = ty + math.sin(d) * mx + math.cos(d) * my
    assert len(wx) > 0
    assert np.all(np.abs(wx - 2.575) < m.cell + 0.15 * math.tan(math.pi / 8))
    assert wy.max() - wy.min() > 0.25
    short = runs[0.5].summary()
    assert short["waypoints_reached"] == 0 or short["collisions"] > 3 * s["collisions"]


def test_the_drives_ranger_sees_a_low_contrast_step_only_inside_its_band():
    """A noise-free floor (grey 100) meeting a face 15 % brighter at a given ground range: a
    step under the default 24 % floor, over the drive's 12 % band floor. The drive's ranger
    finds it at 0.9 m (inside its 0.6-1.2 m band), not at 2 m; without the band, nowhere. A
    configuration's own band wins over the drive's."""
    from floorscan.drive.loop import drive_ranger

    camera = Camera()
    table = make_table(camera, "exact")
    w, h = table.image_width, table.image_height
    u, v = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    x, y = table.lookup(u, v)
    ground_range = np.hypot(x, y)

    def image(step_at_m):
        beyond = ~np.isfinite(ground_range) | (ground_range > step_at_m)
        return np.where(beyond, 115, 100).astype(np.uint8)

    def boundaries(ranger, step_at_m):
        scan = ranger.scan(image(step_at_m))
        st = np.asarray(scan.status_codes)
        r = np.hypot(np.asarray(scan.x), np.asarray(scan.y))
        return (st == 0) & (np.abs(r - step_at_m) < 0.05), len(st)

    with_band = drive_ranger(table, DriveOptions())
    found, n = boundaries(with_band, 0.9)
    assert found.sum() > 0.8 * n
    assert boundaries(with_band, 2.0)[0].sum() == 0
    without = drive_ranger(table, DriveOptions(mid_range_m=None))
    assert boundaries(without, 0.9)[0].sum() == 0
    cfg = Config().with_overrides({"ranger.mid_range_m": [1.5, 2.5]})
    theirs = drive_ranger(table, DriveOptions(), cfg)
    assert boundaries(theirs, 0.9)[0].sum() == 0
    assert boundaries(theirs, 2.0)[0].sum() > 0.5 * n
    with pytest.raises(OptionError, match="mid_range_m"):
        DriveOptions(mid_range_m=(1.2, 0.6))
    with pytest.raises(OptionError, match="mid_contrast"):
        DriveOptions(mid_contrast=-1.0)


@pytest.mark.parametrize("persist_range", [0.5, 0.0])
def test_a_box_seen_near_enters_the_planners_map_on_its_second_frame(persist_range):
    """A box whose face the camera sees 0.4 m away for the first time (rendered, ranged):
    with `persist_range_m` 0.5 the map's own evidence takes the face at once and the
    planner's obstacles on the next frame, which sees it again; with 0 both at once. The
    face's cells come from the world's geometry, not from the map."""
    camera = Camera()
    table = make_table(camera, "exact")
    ranger = VisualRanger(table, columns=160)
    model = VisualSensorModel(persist_range_m=persist_range)
    world = World.from_toml(HALL + BOX)
    face_x = 2.8 - 0.225
    pose = (face_x - 0.4 - camera.robot_from_camera[0], 1.5, 0.0)
    m = AvoidanceMap(center=pose[:2])
    fx, fy = m.to_cells(np.full(5, face_x + 0.01), np.linspace(1.4, 1.6, 5))
    cells = (fy.astype(int), fx.astype(int))
    occupied_nats = math.log(m.options.occupied_threshold / (1 - m.options.occupied_threshold))
    seen = []
    for k in range(2):
        image, _ = render(world, camera, pose, frame=k)
        m.insert_visual(
            ranger.scan(image), pose, mount=camera.robot_from_camera, table=table, model=model
        )
        seen.append((m.log_odds[cells] > occupied_nats, m.occupied()[cells]))
    (own_first, plan_first), (own_second, plan_second) = seen
    assert own_first.all() and own_second.all()
    assert plan_second.all()
    if persist_range > 0:
        assert not plan_first.any()
        assert m.plan_near_hits[cells].all()
    else:
        assert plan_first.all()
        assert not m.plan_near_hits.any()


def test_the_drive_table_of_the_config_gives_the_map_and_the_sensor_model():
    cfg = Config.from_toml(
        "[drive.avoidance_map]\nsize_m = 6.0\n[drive.sensor_model]\nconfirm_range_m = 0.5\n"
        "[drive.costmap]\nrobot_radius_m = 0.2\n[drive.dwa]\nvth_samples = 11\n"
    )
    o = with_drive_tables(DriveOptions(), cfg)
    assert o.map.size_m == 6.0 and o.model.confirm_range_m == 0.5
    assert o.costmap.robot_radius_m == 0.2 and o.dwa.vth_samples == 11
    # the other fields keep the Rust defaults, the same as the Python objects'
    assert o.map.replace(size_m=8.0) == AvoidanceMapOptions()
    assert (
        o.model.replace(confirm_range_m=VisualSensorModel().confirm_range_m) == VisualSensorModel()
    )
    # a round trip through the written file keeps the table
    assert Config.from_toml(cfg.to_toml()).drive.options() == cfg.drive.options()
    with pytest.raises(ConfigError, match="fusion_weight"):
        Config.from_toml("[drive.sensor_model]\nfusion_weight = 2.0\n")
