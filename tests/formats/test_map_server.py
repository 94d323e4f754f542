"""ROS map_server maps: round trips, maps written the way map_saver writes them, errors."""

import math

import floorscan
import numpy as np
import pytest
from floorscan import FileFormatError, OccupancyGrid, OptionError
from floorscan.formats.map_server import read_map_yaml, save_map
from PIL import Image


def sample_grid(**kw):
    g = OccupancyGrid(cell_size_m=0.05, origin_m=(-1.3, 2.2), **kw)
    rng = np.random.default_rng(7)
    ranges = rng.uniform(0.3, 1.5, size=90)
    for k in range(6):
        g.insert_laser(
            ranges,
            angle_min=-math.pi,
            angle_increment=2 * math.pi / 90,
            range_max_m=1.4,
            pose=(0.1 * k, 2.5, 0.2 * k),
        )
    return g


def test_trinary_round_trip_keeps_classes_and_geometry(tmp_path):
    g = sample_grid()
    path = g.save(tmp_path / "map.yaml")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.pgm", "map.yaml"]
    back = OccupancyGrid.load(path)
    assert back.cell_size_m == g.cell_size_m
    assert (back.extent.x_cell, back.extent.y_cell) == (0, 0)  # the image's lattice
    assert back.extent.origin_m == pytest.approx(g.extent.origin_m, abs=1e-12)
    assert back.extent.shape == g.extent.shape
    np.testing.assert_array_equal(back.occupancy_classes(back.extent), g.occupancy_classes())
    # And a second round trip is exact.
    again = OccupancyGrid.load(back.save(tmp_path / "again.yaml"), grow=True)
    np.testing.assert_array_equal(again.raw(back.extent), back.raw())
    # A growing grid takes more data around the loaded map; a fixed one refuses poses outside.
    again.insert_laser([1.0], angles=[0.0], range_max_m=2.0, pose=(50.0, 50.0, 0.0))
    with pytest.raises(floorscan.OutOfBoundsError):
        back.insert_laser([1.0], angles=[0.0], range_max_m=2.0, pose=(50.0, 50.0, 0.0))


def test_scale_round_trip_keeps_probabilities(tmp_path):
    g = sample_grid()
    back = OccupancyGrid.load(save_map(g, tmp_path / "m.yml", mode="scale"))
    known = g.raw() != 0
    p_back = back.probabilities(back.extent)
    np.testing.assert_allclose(p_back[known], g.probabilities()[known], atol=1.0 / 255 + 1e-3)
    assert np.all(np.abs(p_back[~known] - 0.5) < 0.003)
    assert read_map_yaml(tmp_path / "m.yml")["mode"] == "scale"


def test_files_are_map_saver_compatible(tmp_path):
    g = sample_grid()
    g.save(tmp_path / "map.yaml")
    meta = read_map_yaml(tmp_path / "map.yaml")
    assert meta["resolution"] == 0.05 and meta["negate"] == 0
    assert (meta["occupied_thresh"], meta["free_thresh"]) == (0.65, 0.196)
    raw = (tmp_path / "map.pgm").read_bytes()
    assert raw.startswith(b"P5\n")
    with Image.open(tmp_path / "map.pgm") as im:
        pixels = np.asarray(im)
    assert set(np.unique(pixels)) <= {0, 205, 254}
    # Row 0 of the image is the top (highest y).
    np.testing.assert_array_equal(pixels[::-1] == 0, g.occupancy_classes() == 2)


def test_reads_a_hand_written_ros_map(tmp_path):
    # A 4 x 3 map as map_saver would write it, with comments, quotes and negate.
    pixels = np.array([[0, 254, 205, 254], [254, 254, 254, 0], [205, 205, 0, 254]], np.uint8)
    Image.fromarray(255 - pixels).save(tmp_path / "neg.png")
    (tmp_path / "room.yaml").write_text(
        "# saved by hand\nimage: 'neg.png'\nresolution: 0.1  # m/pixel\norigin: [-0.2, 0.5, 0.0]\n"
        "negate: 1\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    g = OccupancyGrid.load(tmp_path / "room.yaml")
    e = g.extent
    assert (e.width, e.height) == (4, 3) and e.origin_m == pytest.approx((-0.2, 0.5))
    expected = np.select([pixels == 0, pixels == 254], [2, 0], 1)  # occupied 2, free 0, unknown 1
    np.testing.assert_array_equal(g.occupancy_classes(e)[::-1], expected)
    # The bottom-left pixel is cell (0, 0), at the origin: x in [-0.2, -0.1), y in [0.5, 0.6).
    assert g.is_free(-0.15, 0.55) is False and g.is_occupied(-0.15, 0.55) is False  # 205: unknown
    assert g.is_occupied(0.05, 0.55) and g.is_free(-0.05, 0.65) and g.is_occupied(-0.15, 0.75)


def test_transparent_pixels_are_unknown(tmp_path):
    rgba = np.zeros((2, 2, 4), np.uint8)
    rgba[..., :3] = 0  # black: occupied
    rgba[..., 3] = 255
    rgba[0, 0, 3] = 0
    Image.fromarray(rgba, mode="RGBA").save(tmp_path / "a.png")
    (tmp_path / "a.yaml").write_text(
        "image: a.png\nresolution: 1.0\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    classes = OccupancyGrid.load(tmp_path / "a.yaml").occupancy_classes(
        floorscan.GridExtent(0, 0, 2, 2, 1.0, (0.0, 0.0))
    )
    assert classes[::-1].tolist() == [[1, 2], [2, 2]]


@pytest.mark.parametrize(
    "text, message",
    [
        ("resolution: 0.05\norigin: [0, 0, 0]\n", "image"),
        ("image: m.pgm\norigin: [0, 0, 0]\n", "resolution"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0]\n", ":3: `origin`"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0.5]\n", "rotated"),
        ("image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n", "resolution"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: fancy\n", ":4: `mode`"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 2\n", "negate"),
        ("image: m.pgm\n  nested: 1\n", ":2: invalid YAML"),
        ("image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nfree_thresh: 0.9\n", "free_thresh"),
    ],
)
def test_bad_yaml_is_reported_with_its_line(tmp_path, text, message):
    (tmp_path / "m.yaml").write_text(text)
    with pytest.raises(FileFormatError, match=message.replace("[", r"\[")):
        OccupancyGrid.load(tmp_path / "m.yaml")


def test_missing_or_broken_image_and_bad_save_arguments(tmp_path):
    (tmp_path / "m.yaml").write_text("image: nothere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(FileFormatError, match="nothere.pgm"):
        OccupancyGrid.load(tmp_path / "m.yaml")
    g = sample_grid()
    with pytest.raises(OptionError, match="yaml"):
        g.save(tmp_path / "map.txt")
    with pytest.raises(OptionError, match="mode"):
        g.save(tmp_path / "map.yaml", mode="raw")
    with pytest.raises(OptionError, match="origin_m"):
        OccupancyGrid.load(tmp_path / "m.yaml", origin_m=(0, 0))
