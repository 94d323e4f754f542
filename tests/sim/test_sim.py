"""floorscan.sim: worlds, cameras and exact geometry, rendering with truth, robot and odometry.
Every expectation is independent of the renderer: analytic geometry, the lens model's own
projection, floorscan-core's ground table, or statistics of the noise parameters."""

from __future__ import annotations

import math

import numpy as np
import pytest
from floorscan import (
    CameraMount,
    FileFormatError,
    FloorscanError,
    GroundTable,
    Lens,
    OptionError,
    WorldError,
)
from floorscan.sim import (
    OCCUPIED,
    PIXEL_LABELS,
    Camera,
    Imaging,
    OdometryNoise,
    Robot,
    World,
    render,
    simulate_run,
)

FLOOR_LABELS = {PIXEL_LABELS.index(n) for n in ("carpet", "other_covering", "paper")}
OBSTACLE = PIXEL_LABELS.index("obstacle")


def wall_world(d: float) -> World:
    """Carpet with one long straight wall whose face is at x = d (camera ground frame of a
    robot whose camera sits at the origin)."""
    x = d + 0.05
    return World.from_toml(
        f'name = "wall"\n[start]\nx = 0\ny = 0\n[[walls]]\nfrom = [{x}, -30]\nto = [{x}, 30]\n'
    )


def camera_at_origin_pose(cam: Camera):
    """The robot pose that puts the camera ground frame at the world origin, facing +x."""
    x, y, yaw = cam.robot_from_camera
    c, s = math.cos(-yaw), math.sin(-yaw)
    return (-(c * x - s * y), -(s * x + c * y), -yaw)


# --- worlds ------------------------------------------------------------------------------------


def test_builtin_worlds_load_with_a_tour():
    names = World.builtin_names()
    assert set(names) == {"corridor", "room", "lab", "tiles", "parquet", "patterned"}
    for name in names:
        w = World.builtin(name)
        assert w.name == name and len(w.tour) >= 3 and w.source
    xmin, _, xmax, _ = World.builtin("corridor").bounds
    assert xmax - xmin >= 15.0


def test_world_file_errors_name_the_line_or_the_field(tmp_path):
    bad_value = tmp_path / "bad_value.toml"
    bad_value.write_text(
        'name = "w"\n[start]\nx = 0\ny = 0\n[[walls]]\nfrom = [0, 0]\nto = [1, 0]\nheight_m = -2\n'
    )
    with pytest.raises(WorldError, match=r"walls\[0\]\.height_m") as e:
        World.load(bad_value)
    assert isinstance(e.value, FileFormatError) and isinstance(e.value, FloorscanError)
    assert str(bad_value) in str(e.value)
    bad_type = tmp_path / "bad_type.toml"
    bad_type.write_text('name = "w"\n[start]\nx = 0\ny = "left"\n')
    with pytest.raises(WorldError, match="line 4"):
        World.load(bad_type)
    unknown = tmp_path / "unknown.toml"
    unknown.write_text('name = "w"\ncolour = "red"\n[start]\nx = 0\ny = 0\n')
    with pytest.raises(WorldError, match="colour"):
        World.load(unknown)
    with pytest.raises(WorldError, match="cannot read"):
        World.load(tmp_path / "missing.toml")
    with pytest.raises(OptionError, match="no built-in world"):
        World.builtin("castle")
    for shadow, field in (("strength = 2.0", "strength"), ("length_m = 0.0", "length_m")):
        text = f'name = "w"\n[start]\nx = 0\ny = 0\n[lighting]\ncontact_shadow = {{ {shadow} }}\n'
        with pytest.raises(WorldError, match=rf"lighting\.contact_shadow\.{field}") as e:
            World.from_toml(text)
        assert "\n" not in str(e.value)


def test_contact_shadows_darken_only_the_floor_next_to_what_stands_on_it():
    """A box 1.5 m ahead: with contact shadows the floor right before its foot reads darker by
    about the model's factor there (half the light at the foot, 4 cm scale); the floor far
    from it, the box and the labels are unchanged."""
    cam = Camera(imaging=Imaging.ideal())
    text = (
        'name = "s"\n[start]\nx = 0\ny = 0\n[lighting]\nexposure_jitter = 0.0\n{}'
        "[[boxes]]\nrect = [1.3, -1.0, 2.3, 1.0]\nheight_m = 0.5\n"
    )
    lit = World.from_toml(text.format(""))
    dark = World.from_toml(text.format("contact_shadow = { strength = 0.5, length_m = 0.04 }\n"))
    pose = (0.0, 0.0, 0.0)
    a, truth = render(lit, cam, pose)
    b, truth_b = render(dark, cam, pose)
    assert np.array_equal(truth.labels, truth_b.labels)
    floor = np.isin(truth.labels, list(FLOOR_LABELS))
    # each floor pixel's distance to the box's foot, from the camera's exact ground mapping
    # (the robot at the origin: the camera's ground frame is the robot's moved by the mount)
    v, u = np.nonzero(floor)
    x, y = cam.pixel_to_ground(u.astype(float), v.astype(float))
    mx, my, _ = cam.robot_from_camera
    rx, ry = x + mx, y + my
    d = np.hypot(np.maximum(np.maximum(1.3 - rx, rx - 2.3), 0), np.maximum(np.abs(ry) - 1.0, 0))
    ratio = b[v, u].astype(float) / np.maximum(a[v, u].astype(float), 1)
    near, far = d < 0.02, d > 0.3
    assert near.sum() > 20 and far.sum() > 1000
    assert 0.4 < np.median(ratio[near]) < 0.65  # the factor at 0-2 cm: 0.50-0.59
    assert np.all(b[v, u][far] == a[v, u][far])
    assert np.array_equal(a[~floor], b[~floor])


# --- cameras and the exact image-to-ground mapping --------------------------------------------


def test_exact_mapping_is_the_core_ground_table_of_the_same_lens_and_mount():
    cam = Camera()
    table = cam.ground_table(spacing_px=1, max_range_m=10.0)
    core = GroundTable.from_camera(
        cam.lens, cam.mount, image_width=320, image_height=240, spacing_px=1
    )
    assert np.array_equal(
        np.nan_to_num(table.nodes[0], nan=-1), np.nan_to_num(core.nodes[0], nan=-1)
    )
    v, u = np.mgrid[0:240:7, 0:320:9].astype(np.float64)
    x, y = cam.pixel_to_ground(u, v, max_range_m=10.0)
    tx, ty = table.lookup(u, v)
    both = np.isfinite(x) & np.isfinite(tx)
    assert both.sum() > 500
    assert np.allclose(x[both], tx[both], atol=1e-9) and np.allclose(y[both], ty[both], atol=1e-9)


@pytest.mark.parametrize(
    "lens",
    [
        Lens.equidistant(f=110.0, cx=159.5, cy=119.5),
        Lens.kannala_brandt(fx=135.0, fy=133.0, cx=160.2, cy=118.7, k1=-0.012, k2=0.002),
        Lens.pinhole_radial(fx=180.0, fy=180.0, cx=160.0, cy=120.0, k1=-0.2, k2=0.03),
    ],
)
def test_pixel_ground_pixel_round_trip(lens):
    cam = Camera(lens=lens, mount=CameraMount(height_m=0.35, tilt_rad=0.7, roll_rad=0.02))
    v, u = np.mgrid[100:240:5, 0:320:5].astype(np.float64)
    x, y = cam.pixel_to_ground(u, v, max_range_m=20.0)
    ok = np.isfinite(x)
    assert ok.sum() > 400
    bu, bv = cam.ground_to_pixel(x[ok], y[ok])
    assert np.max(np.abs(bu - u[ok])) < 1e-6 and np.max(np.abs(bv - v[ok])) < 1e-6


def test_a_wall_at_a_known_distance_gives_the_rows_and_points_the_lens_predicts():
    cam = Camera(imaging=Imaging.ideal())
    pose = camera_at_origin_pose(cam)
    for d in (0.8, 2.0):
        image, truth = render(wall_world(d), cam, pose)
        b = truth.status_names == "boundary"
        assert b.sum() > 250
        cols = np.nonzero(b)[0]
        # The floor point at the boundary lies on the wall's foot...
        assert np.allclose(truth.points[b, 0], d, atol=1e-7)
        # ... and the lens model projects it back to (column, boundary row).
        u, v = cam.ground_to_pixel(truth.points[b, 0], truth.points[b, 1])
        assert np.allclose(u, cols, atol=1e-6) and np.allclose(v, truth.rows[b], atol=1e-6)
        # Straight ahead: the row where the optical axis column meets the wall's foot.
        mid = cam.ground_to_pixel(d, 0.0)
        k = int(np.argmin(np.abs(cols - mid[0])))
        col = cols[k]
        y_at = truth.points[b, 1][k]
        assert abs(cam.ground_to_pixel(d, y_at)[1] - truth.rows[col]) < 1e-6
        # Pixels below the row see floor, the one above sees the wall.
        for c in cols[::20]:
            r = truth.rows[c]
            assert set(truth.labels[int(math.floor(r)) + 1 :, c]) <= FLOOR_LABELS
            assert truth.labels[int(math.floor(r)), c] == OBSTACLE


def test_rendering_agrees_with_the_exact_mapping_in_a_real_world():
    cam = Camera()
    image, truth = render(World.builtin("corridor"), cam, (3.0, 0.1, 0.2), seed=3)
    b = np.nonzero(truth.status_names == "boundary")[0]
    assert len(b) > 200
    x, y = cam.pixel_to_ground(b.astype(float), truth.rows[b], max_range_m=1e9)
    assert np.allclose(x, truth.points[b, 0], atol=1e-5) and np.allclose(
        y, truth.points[b, 1], atol=1e-5
    )
    # World points are the camera points placed by world_from_camera.
    cx, cy, cyaw = truth.world_from_camera
    wx = cx + math.cos(cyaw) * truth.points[b, 0] - math.sin(cyaw) * truth.points[b, 1]
    assert np.allclose(wx, truth.points_world[b, 0], atol=1e-9)
    # Floor pixels are darker than the baseboard-free wall far above them? Not asserted; but
    # every boundary column has floor below and an obstacle right above the boundary row.
    for c in b[::16]:
        r = truth.rows[c]
        assert set(truth.labels[int(math.floor(r)) + 1 :, c]) <= FLOOR_LABELS
        assert truth.labels[int(math.floor(r)), c] == OBSTACLE


def test_the_same_seed_gives_the_same_bytes():
    w, cam = World.builtin("lab"), Camera()
    a, ta = render(w, cam, (2.0, 0.0, 0.1), seed=11, frame=4)
    b, tb = render(w, cam, (2.0, 0.0, 0.1), seed=11, frame=4)
    assert a.tobytes() == b.tobytes() and ta.labels.tobytes() == tb.labels.tobytes()
    c, _ = render(w, cam, (2.0, 0.0, 0.1), seed=12, frame=4)
    assert a.tobytes() != c.tobytes()
    small = Camera(width=80, height=60)
    r1 = simulate_run(w, camera=small, seconds=1.0, seed=5, threads=1)
    r2 = simulate_run(w, camera=small, seconds=1.0, seed=5, threads=2)
    assert r1.images.tobytes() == r2.images.tobytes()
    assert r1.odometry.tobytes() == r2.odometry.tobytes()
    assert np.array_equal(r1.truth.status, r2.truth.status)


def test_the_image_looks_like_a_camera_image():
    cam = Camera()
    image, truth = render(World.builtin("corridor"), cam, (1.0, 0.0, 0.0))
    carpet = image[truth.labels == PIXEL_LABELS.index("carpet")].astype(float)
    # Carpet: mid grey, low contrast but not flat (texture and noise).
    assert 50 < carpet.mean() < 160 and 2.0 < carpet.std() < 15.0
    assert (image == 255).mean() < 0.01 and (image == 0).mean() < 0.01
    ideal, _ = render(World.builtin("corridor"), cam.with_imaging(Imaging.ideal()), (1.0, 0.0, 0.0))
    assert np.abs(ideal.astype(int) - image.astype(int)).mean() > 1.0


# --- robot and odometry ------------------------------------------------------------------------


def test_zero_odometry_noise_gives_the_truth():
    tr = Robot(odometry=OdometryNoise.none()).drive(
        start=(1.0, 0.0, 0.0), seconds=20, waypoints=[(3, 0), (3, 2)]
    )
    assert np.array_equal(tr.poses, tr.odometry)
    assert len(tr) == 201 and tr.timestamps[1] == pytest.approx(0.1)


def test_systematic_odometry_errors_follow_their_parameters():
    straight = [(10.0, 0.2, 0.0)]  # 2 m straight
    tr = Robot(
        odometry=OdometryNoise.none().__class__(
            wheel_sigma_per_sqrt_m=0,
            radius_scale_error=0.05,
            radius_difference=0,
            wheelbase_error=0,
        )
    ).drive(start=(0, 0, 0), seconds=12, commands=straight)
    assert tr.poses[-1][0] == pytest.approx(2.0, abs=1e-9)
    assert tr.odometry[-1][0] == pytest.approx(2.1, abs=1e-9)
    bend = Robot(
        odometry=OdometryNoise(
            wheel_sigma_per_sqrt_m=0,
            radius_scale_error=0,
            radius_difference=0.01,
            wheelbase_error=0,
        )
    ).drive(start=(0, 0, 0), seconds=12, commands=straight)
    # Heading drift = distance * difference / wheelbase.
    assert bend.odometry[-1][2] == pytest.approx(2.0 * 0.01 / 0.3, rel=1e-9)


def test_random_odometry_error_statistics_match_sigma():
    sigma = 0.03
    robot = Robot(
        odometry=OdometryNoise(
            wheel_sigma_per_sqrt_m=sigma,
            radius_scale_error=0,
            radius_difference=0,
            wheelbase_error=0,
        )
    )
    yaw = np.array(
        [
            robot.drive(start=(0, 0, 0), seconds=5, commands=[(5.0, 0.2, 0.0)], seed=s).odometry[
                -1
            ][2]
            for s in range(1500)
        ]
    )
    # 1 m per wheel: heading variance 2 sigma^2 D / b^2, zero mean.
    expected = 2 * sigma**2 * 1.0 / 0.3**2
    assert yaw.var() == pytest.approx(expected, rel=0.15)
    assert abs(yaw.mean()) < 4 * math.sqrt(expected / len(yaw))


def test_options_are_validated_on_construction():
    with pytest.raises(OptionError, match="vignetting"):
        Imaging(vignetting=2.0)
    with pytest.raises(OptionError, match="speed_mps"):
        Robot(speed_mps=-1)
    with pytest.raises(OptionError, match="wheelbase_error"):
        OdometryNoise(wheelbase_error=3)
    with pytest.raises(OptionError, match="unknown option"):
        Robot(sped=1)
    with pytest.raises(OptionError, match="width"):
        Camera(width=4)
    with pytest.raises(TypeError):
        Camera(lens="fisheye")
    with pytest.raises(OptionError):
        Robot().drive(start=(0, 0, 0), seconds=1)


# --- occupancy ---------------------------------------------------------------------------------


def test_occupancy_raster_and_map_server_files(tmp_path):
    w = World.builtin("room")
    r = w.occupancy(resolution_m=0.04)
    assert r.value_at(*w.start[:2]) == 0
    assert r.value_at(3.84, 1.0) == OCCUPIED  # east wall
    assert r.value_at(1.92, 1.92) == 0  # under the table top: the robot fits
    yaml = r.write_map_server(tmp_path / "room.yaml")
    text = yaml.read_text()
    assert "image: room.pgm" in text and "resolution: 0.04" in text and "mode: trinary" in text
    for key in ("origin:", "negate: 0", "occupied_thresh:", "free_thresh:"):
        assert key in text
    data = (tmp_path / "room.pgm").read_bytes()
    header, pixels = data.split(b"\n", 3)[:3], data.split(b"\n", 3)[3]
    assert header[0] == b"P5"
    wpx, hpx = (int(s) for s in header[1].split())
    img = np.frombuffer(pixels, dtype=np.uint8).reshape(hpx, wpx)
    assert set(np.unique(img)) <= {0, 205, 254}
    # The start position in the image (top row = highest y).
    ox, oy = r.origin
    i = int((w.start[0] - ox) / 0.04)
    j = hpx - 1 - int((w.start[1] - oy) / 0.04)
    assert img[j, i] == 254


def test_the_truth_map_reads_back_with_floorscans_map_server_reader(tmp_path):
    from floorscan import OccupancyGrid

    w = World.builtin("corridor")
    r = w.occupancy(resolution_m=0.05)
    grid = OccupancyGrid.load(r.write_map_server(tmp_path / "truth.yaml"))
    x, y = w.start[:2]
    assert grid.is_free(x, y) and not grid.is_occupied(x, y)
    assert grid.is_occupied(10.0, 1.0)  # the corridor's north wall, between doors
    # Every cell agrees with the raster.
    rng = np.random.default_rng(0)
    xmin, ymin, xmax, ymax = w.bounds
    for px, py in zip(rng.uniform(xmin, xmax, 500), rng.uniform(ymin, ymax, 500)):
        v = r.value_at(px, py)
        assert grid.is_occupied(px, py) == (v == OCCUPIED)
        assert grid.is_free(px, py) == (v == 0)


ROOM_WITH_A_BOX = """name = "w"
tour = [[1.0, 1.0], [3.0, 1.0]]
[start]
x = {x}
y = {y}
[[walls]]
from = [0, 0]
to = [4, 0]
[[walls]]
from = [4, 0]
to = [4, 3]
[[walls]]
from = [4, 3]
to = [0, 3]
[[walls]]
from = [0, 3]
to = [0, 0]
[[boxes]]
rect = [1.7, 1.7, 2.3, 2.3]
height_m = 0.7
"""


@pytest.mark.parametrize(
    "x, y, where", [(2.0, 0.0, "on a wall"), (2.0, 2.0, "inside the box"), (1.71, 2.0, "its edge")]
)
def test_a_start_pose_that_is_not_on_free_floor_is_refused(tmp_path, x, y, where):
    """A robot placed in a wall or an obstacle would be "simulated" stuck there."""
    path = tmp_path / "w.toml"
    path.write_text(ROOM_WITH_A_BOX.format(x=x, y=y))
    with pytest.raises(WorldError, match=r"start pose .* lies inside a wall or an obstacle") as e:
        World.load(path)
    assert str(path) in str(e.value), where


def test_a_start_pose_on_free_floor_loads():
    world = World.from_toml(ROOM_WITH_A_BOX.format(x=1.0, y=1.0))
    assert world.start[:2] == (1.0, 1.0)
    # beside the box but clear of it, as a robot parked next to furniture
    assert World.from_toml(ROOM_WITH_A_BOX.format(x=1.55, y=2.0)).start[0] == 1.55
