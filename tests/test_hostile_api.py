"""Issue 12's hostile inputs through the Python API: every error is a FloorscanError (also a
ValueError / TypeError where it fits), no Rust panic reaches Python, no value allocates the
machine, and garbage that used to be accepted is refused or normalised."""

from __future__ import annotations

import dataclasses
import json
import math

import floorscan
import numpy as np
import pytest
from floorscan import (
    DatasetError,
    FileFormatError,
    FloorscanError,
    GroundTable,
    OccupancyGrid,
    OptionError,
    OutOfBoundsError,
    Scan,
)
from floorscan.errors import InternalError
from floorscan.formats.dataset import read_images_txt
from floorscan.formats.image_io import read_grey
from floorscan.formats.trajectory import read_tum, yaw_from_quaternion
from floorscan.ranging.scan import parse_scans_csv, scans_to_csv
from hostile_corpus import png_claiming, table_json
from synthetic_dataset import camera_table


def test_a_panic_in_the_native_module_arrives_as_internal_error():
    with pytest.raises(InternalError, match="deliberate panic") as e:
        floorscan._native._panic_for_tests()
    assert isinstance(e.value, FloorscanError) and type(e.value).__name__ != "PanicException"


def test_ground_table_sizes_that_overflow_or_exceed_the_limits_are_file_format_errors():
    big = 1 << 33
    overflow = table_json(
        image_width=big,
        image_height=1 << 31,
        spacing_px=1,
        nodes_u=big,
        nodes_v=1 << 31,
        x_m=[],
        y_m=[],
    )
    with pytest.raises(FileFormatError):
        GroundTable.from_json(overflow)
    with pytest.raises(FileFormatError, match="larger than"):
        GroundTable.from_json(table_json(image_width=10**9, image_height=10**9, spacing_px=10**9))
    with pytest.raises(FileFormatError):
        GroundTable.from_json(None)
    # The small valid one loads, scans and looks up without a panic.
    t = GroundTable.from_json(table_json())
    assert t.image_width == 4
    x, _ = t.lookup(np.array([1.5]), np.array([1.5]))
    assert np.isfinite(x[0])


def test_fixed_bounds_beyond_max_cells_are_refused_at_construction():
    with pytest.raises(OptionError, match="max_cells"):
        OccupancyGrid(bounds_m=((0, 0), (1e4, 1e4)))
    g = OccupancyGrid(bounds_m=((0, 0), (1e4, 1e4)), cell_size_m=2.0)
    assert g.extent.width == 5000


def test_a_pose_1000_km_away_is_an_error_not_an_allocation():
    g = OccupancyGrid()
    g.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0.0, 0.0, 0.0))
    before = g.raw().copy()
    for x in (1e5, 1e6):
        with pytest.raises(OutOfBoundsError, match="max_cells"):
            g.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(x, 0.0, 0.0))
    np.testing.assert_array_equal(g.raw(), before)
    assert g.memory_bytes < 1 << 20
    # A larger limit accepts the same pose (the limit is an option, not a wall).
    big = OccupancyGrid(max_cells=1 << 32)
    big.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(2e3, 0.0, 0.0))


def test_raw_and_write_raw_refuse_huge_negative_and_wrapping_rectangles():
    g = OccupancyGrid(cell_size_m=0.1)
    e = g.extent
    huge = dataclasses.replace(e, width=10**6, height=10**6)
    with pytest.raises(OutOfBoundsError, match="max_cells"):
        g.raw(huge)
    with pytest.raises(OutOfBoundsError):
        g.raw(dataclasses.replace(e, width=-1))
    with pytest.raises(OutOfBoundsError):
        g.raw(dataclasses.replace(e, x_cell=2**40))
    values = np.full((2, 3), 500, np.int16)
    for x in (2**31 - 1, 2**31, -(2**40)):
        with pytest.raises(OutOfBoundsError):
            g.write_raw(values, x_cell=x, y_cell=0)
    with pytest.raises(FloorscanError):
        g.write_raw(values, x_cell="a", y_cell=0)
    # In range, the write is read back exactly.
    g.write_raw(values, x_cell=1000, y_cell=-7)
    np.testing.assert_array_equal(g.raw(g.extent), values)


def test_bad_argument_types_are_floorscan_errors_and_type_errors():
    g = OccupancyGrid()
    with pytest.raises(FloorscanError) as e:
        g.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0.0, 0.0))
    assert isinstance(e.value, TypeError)
    with pytest.raises(FloorscanError) as e:
        g.insert_scan("not a scan", pose=(0, 0, 0))
    assert isinstance(e.value, TypeError)
    ranger = floorscan.VisualRanger(camera_table(), columns=8)
    image = np.zeros((ranger.table.image_height, ranger.table.image_width), np.uint8)
    with pytest.raises(FloorscanError) as e:
        ranger.scan(image, timestamp="abc")
    assert isinstance(e.value, ValueError)
    with pytest.raises(FloorscanError):
        floorscan.VisualRanger("table.json")


def test_decompression_bombs_are_image_and_format_errors(tmp_path):
    (tmp_path / "bomb.png").write_bytes(png_claiming(40000, 40000))
    with pytest.raises(floorscan.ImageError, match="pixels"):
        read_grey(tmp_path / "bomb.png")
    (tmp_path / "map.yaml").write_text(
        "image: bomb.png\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    with pytest.raises(FileFormatError, match="pixels"):
        OccupancyGrid.load(tmp_path / "map.yaml")


def test_hostile_pngs_through_the_rust_decoder_are_one_line_image_errors(tmp_path):
    """Issue 14: truncated data, a header claiming 2^31 x 2^31 pixels (no allocation), an
    impossible bit depth, and a file too big to read whole (left to Pillow's lazy reader)."""
    good = png_claiming(8, 1)
    cases = {
        "truncated.png": good[: len(good) - 20],
        "huge.png": png_claiming(0x7FFFFFFF, 0x7FFFFFFF),
        "depth.png": good[:24] + b"\x03" + good[25:],  # grey with 3 bits: no such PNG
    }
    for name, data in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(floorscan.ImageError) as e:
            read_grey(tmp_path / name)
        assert "\n" not in str(e.value) and name in str(e.value)
    from floorscan.formats import image_io

    try:
        image_io.set_max_image_pixels(4)  # files over 64 MiB + 64 bytes go to Pillow unread
        big = tmp_path / "big.png"
        with open(big, "wb") as f:
            f.write(png_claiming(8, 1))
            f.truncate((64 << 20) + 1000)  # sparse: no disk used
        with pytest.raises(floorscan.ImageTooLargeError, match="8 x 1"):
            read_grey(big)
    finally:
        image_io.set_max_image_pixels(image_io.DEFAULT_MAX_IMAGE_PIXELS)


@pytest.mark.parametrize("scale", [1.0, 3.0, 0.01])
def test_quaternions_are_normalised(scale):
    yaw = math.pi / 2
    q = np.array([0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)]) * scale
    assert yaw_from_quaternion(*q) == pytest.approx(yaw, abs=1e-12)


def test_a_non_unit_quaternion_in_odometry_reads_as_its_rotation(tmp_path):
    s = math.sqrt(0.5)
    (tmp_path / "o.txt").write_text(f"1.0 0 0 0 0 0 {2 * s} {2 * s}\n2.0 1 0 0 0 0 0 0\n")
    with pytest.raises(DatasetError, match=":2: quaternion"):
        read_tum(tmp_path / "o.txt")
    (tmp_path / "o.txt").write_text(f"1.0 0 0 0 0 0 {2 * s} {2 * s}\n")
    assert read_tum(tmp_path / "o.txt").yaw[0] == pytest.approx(math.pi / 2)


def test_images_txt_must_increase_in_time(tmp_path):
    (tmp_path / "images.txt").write_text("1.0 a.png\n2.0 b.png\n1.5 c.png\n")
    with pytest.raises(DatasetError, match=":3: .*increasing"):
        read_images_txt(tmp_path)
    (tmp_path / "images.txt").write_text("1.0 a.png\n1.0 b.png\n")
    with pytest.raises(DatasetError):
        read_images_txt(tmp_path)
    (tmp_path / "images.txt").write_text("nan a.png\n")
    with pytest.raises(DatasetError, match="finite"):
        read_images_txt(tmp_path)


def test_scans_csv_must_be_in_time_order():
    def scan(t):
        return Scan.from_arrays(
            timestamp=t, columns=[0], rows=[1.0], status=["boundary"], x=[1.0], y=[0.0]
        )

    good = scans_to_csv([scan(1.0), scan(2.0)])
    assert [s.timestamp for s in parse_scans_csv(good)] == [1.0, 2.0]
    bad = scans_to_csv([scan(2.0), scan(1.0)])
    with pytest.raises(FileFormatError, match="time order"):
        list(parse_scans_csv(bad))


def test_sixteen_bit_frames_scan_like_the_eight_bit_frame():
    """The same frame saved x257 as uint16 finds the same boundary points with the same
    threshold (it found 3 points instead of 38 before)."""
    table = camera_table()
    ranger = floorscan.VisualRanger(table, columns=32, threshold=15)
    rng = np.random.default_rng(1)
    h, w = table.image_height, table.image_width
    img = np.where(np.arange(h)[:, None] < 60, 190, 90) + rng.normal(0, 3, (h, w))
    img8 = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    a = ranger.scan(img8)
    b = ranger.scan(img8.astype(np.uint16) * 257)
    assert a.count()["boundary"] >= 30
    np.testing.assert_array_equal(a.status_codes, b.status_codes)
    np.testing.assert_allclose(a.rows, b.rows, equal_nan=True)
    from floorscan.ranging.auto_threshold import texture_noise

    cols = ranger.columns
    n8 = texture_noise([img8], half_width=4, columns=cols, bottom_margin=2)
    n16 = texture_noise([img8.astype(np.uint16) * 257], half_width=4, columns=cols, bottom_margin=2)
    assert n16 == pytest.approx(n8)


def test_config_with_limits_round_trips():
    from floorscan.pipeline.config import Config

    cfg = Config.from_toml("[limits]\nmax_image_pixels = 1000\n[map]\nmax_cells = 4096\n")
    assert cfg.limits.max_image_pixels == 1000 and cfg.grid.max_cells == 4096
    assert json.loads(json.dumps(cfg.to_dict()))["limits"]["max_image_pixels"] == 1000


def test_drive_natives_refuse_bad_grids_windows_and_poses():
    from floorscan._native.drive import geodesic_distances
    from floorscan._native.mapping import correlative_search

    field = np.zeros((4, 4), np.float32)
    pts = np.zeros((3, 2))
    with pytest.raises(FloorscanError):  # a window of 10^12 evaluations
        correlative_search(field, (0, 0), 0.1, pts, (0, 0, 0), 200_000, 10, 0.01, 1, 1)
    with pytest.raises(FloorscanError):  # few evaluations, a padded field of 6 x 10^9 cells
        correlative_search(field, (0, 0), 0.1, pts[:1], (0, 0, 0), 20_000, 0, 0.01, 1, 1)
    with pytest.raises(FloorscanError):
        correlative_search(field, (0, 0), 0.1, pts, (math.nan, 0, 0), 2, 2, 0.01, 1, 1)
    with pytest.raises(FloorscanError):
        correlative_search(field, (0, 0), 0.0, pts, (0, 0, 0), 2, 2, 0.01, 1, 1)
    blocked = np.zeros((3, 3), bool)
    with pytest.raises(FloorscanError):  # a seed outside the grid
        geodesic_distances(blocked, np.ones((3, 3)), np.array([9]), np.array([0.0]), 0.1)
    with pytest.raises(FloorscanError):  # shapes that disagree
        geodesic_distances(blocked, np.ones((3, 4)), np.array([0]), np.array([0.0]), 0.1)
    with pytest.raises(FloorscanError):
        geodesic_distances(blocked, np.full((3, 3), np.nan), np.array([0]), np.array([0.0]), 0.1)


def test_drive_map_natives_refuse_huge_windows_and_mismatched_readings():
    from floorscan._native.drive import AvoidanceMap, coarse_grid
    from floorscan._native.mapping import ScanMatcher
    from floorscan.drive import VisualSensorModel

    with pytest.raises(FloorscanError):  # 10^10 cells: refused by the options, not allocated
        AvoidanceMap({"size_m": 5000.0, "cell_size_m": 0.05}, (0.0, 0.0))
    with pytest.raises(FloorscanError):
        AvoidanceMap({"clamp_nats": [math.nan, 3.5]}, (0.0, 0.0))
    with pytest.raises(FloorscanError):
        AvoidanceMap({}, (math.nan, 0.0))
    m = AvoidanceMap({"size_m": 1.0, "cell_size_m": 0.1}, (0.0, 0.0))
    z, u8 = np.zeros(3), np.zeros(3, np.uint8)
    with pytest.raises(FloorscanError):  # readings of different lengths
        m.insert_visual((0, 0, 0), u8, z, z, z[:2], z, z, z, VisualSensorModel())
    with pytest.raises(FloorscanError, match="persist_range_m"):
        VisualSensorModel(persist_range_m=-1.0)
    with pytest.raises(FloorscanError):  # ranges and angles of different lengths
        m.insert_laser((1.0, 1.0, 0.0), np.ones(2), np.ones(1), 1.0)
    with pytest.raises(FloorscanError):  # a face 10^300 m long between close boundary points
        big = np.array([0.0, 1e300])
        m.insert_visual(
            (0, 0, 0), np.zeros(2, np.uint8), np.array([1.0, 1.0]), big, big * 0, big * 0,
            np.full(2, 1e300), np.zeros(2), VisualSensorModel(),
        )  # fmt: skip
    assert not m.log_odds.any()
    with pytest.raises(FloorscanError):  # 400 m at 1 cm: 1.6 * 10^9 cells, refused
        ScanMatcher({"size_m": 400.0, "cell_size_m": 0.01}, (0.0, 0.0))
    with pytest.raises(FloorscanError):  # a coarse cell larger than the map
        coarse_grid(np.zeros((4, 4), np.uint8), 9, 253, 2.0)
