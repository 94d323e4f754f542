"""Fuzzing the Python readers (issue 12) with hypothesis: configuration TOML, rig.toml,
pattern TOML, images.txt, TUM odometry, CARMEN logs, scans CSV, map_server YAML and bags.
Property: a reader returns a value or raises a FloorscanError, never anything else (no
UnicodeDecodeError, IndexError, OverflowError, MemoryError, ...).

``make test`` runs a short deterministic corpus (the "ci" profile: derandomised, 40 examples
per reader); ``make fuzz`` runs the "fuzz" profile (random, 3000 examples per reader).
"""

from __future__ import annotations

import os
import random

from floorscan import FloorscanError
from floorscan.calibration.pattern import Pattern
from floorscan.formats.carmen import read_carmen
from floorscan.formats.dataset import read_images_txt
from floorscan.formats.map_server import read_map_yaml
from floorscan.formats.rig import read_rig
from floorscan.formats.trajectory import read_tum
from floorscan.pipeline.config import Config
from floorscan.pipeline.config_check import check_config
from floorscan.ranging.scan import parse_scans_csv
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

settings.register_profile(
    "ci",
    max_examples=40,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
settings.register_profile(
    "fuzz",
    max_examples=3000,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
PROFILE = os.environ.get("FLOORSCAN_HYPOTHESIS_PROFILE", "ci")

SEEDS = {
    "config": Config().to_toml(),
    "rig": "[camera]\nx = 0.1\ny = 0.0\nyaw = 0.0\nheight = 0.4\n",
    "pattern": Pattern.checkerboard(
        inner_corners=(7, 5), square=0.1, near_left=(0.6, 0.3)
    ).to_toml(),
    "images": "# timestamp filename\n1.0 images/0.png\n1.1 images/1.png\n1.2 images/2.png\n",
    "tum": "# t x y z qx qy qz qw\n1.0 0 0 0 0 0 0 1\n1.1 0.1 0 0 0 0 0.05 0.9987\n",
    "carmen": "PARAM robot_frontlaser_offset 0.0 nohost 0\n"
    + "FLASER 4 1.0 2.0 81.91 1.5 0.0 0.0 0.0 0.0 0.0 0.0 1.0 sim 1.0\n"
    + "ODOM 0.1 0.0 0.0 0.0 0.0 0.0 1.1 sim 1.1\n",
    "csv": "timestamp,column,row,status,x_m,y_m,range_m,bearing_rad\n"
    + "1.0,3,40.5,boundary,1.2,0.1,1.204,0.083\n1.0,9,nan,no_boundary,nan,nan,inf,0.1\n",
    "yaml": "image: map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
    + "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
}

HOSTILE_TOKENS = [
    "",
    "0",
    "-1",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "1e999",
    "9" * 400,
    "\x00",
    "\udcff",
    "[",
    "]]",
    '"',
    "=",
    "\n",
    "#",
    ",",
    "true",
    "1:2:3",
]


@st.composite
def mutated(draw, seed: str) -> bytes:
    """The seed text with tokens replaced, lines dropped or duplicated, and bytes flipped."""
    rnd = random.Random(draw(st.integers(0, 2**32 - 1)))
    lines = seed.splitlines(keepends=True)
    for _ in range(draw(st.integers(0, 4))):
        if not lines:
            break
        k = rnd.randrange(len(lines))
        action = rnd.randrange(4)
        words = lines[k].split(" ")
        if action == 0 and words:
            words[rnd.randrange(len(words))] = rnd.choice(HOSTILE_TOKENS)
            lines[k] = " ".join(words)
        elif action == 1:
            del lines[k]
        elif action == 2:
            lines.insert(k, lines[k])
        else:
            lines[k] = lines[k][: rnd.randrange(len(lines[k]) + 1)]
    data = bytearray("".join(lines).encode("utf-8", "surrogatepass"))
    for _ in range(draw(st.integers(0, 3))):
        if data:
            data[rnd.randrange(len(data))] = rnd.randrange(256)
    if draw(st.booleans()):
        data += draw(st.binary(max_size=64))
    return bytes(data)


def only_floorscan_errors(fn, *args):
    try:
        return fn(*args)
    except FloorscanError:
        return None


def text_cases(kind: str):
    return st.one_of(mutated(SEEDS[kind]), st.binary(max_size=300))


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("config"))
def test_config_files(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("c") / "c.toml"
    path.write_bytes(data)
    cfg = only_floorscan_errors(Config.load, path)
    if cfg is not None:
        only_floorscan_errors(check_config, cfg)


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("rig"))
def test_rig_files(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("r") / "rig.toml"
    path.write_bytes(data)
    only_floorscan_errors(read_rig, path)


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("pattern"))
def test_pattern_files(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("p") / "pattern.toml"
    path.write_bytes(data)
    pattern = only_floorscan_errors(Pattern.load, path)
    if pattern is not None:
        only_floorscan_errors(pattern.points)


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("images"))
def test_images_txt(tmp_path_factory, data):
    folder = tmp_path_factory.mktemp("d")
    (folder / "images.txt").write_bytes(data)
    only_floorscan_errors(read_images_txt, folder)


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("tum"))
def test_odometry_files(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("o") / "odometry.txt"
    path.write_bytes(data)
    only_floorscan_errors(read_tum, path)


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("carmen"), strict=st.booleans())
def test_carmen_logs(tmp_path_factory, data, strict):
    path = tmp_path_factory.mktemp("l") / "log.txt"
    path.write_bytes(data)
    only_floorscan_errors(lambda: read_carmen(path, strict=strict))


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("csv"))
def test_scans_csv(data):
    only_floorscan_errors(lambda: list(parse_scans_csv(data.decode("utf-8", "replace"))))


@settings(settings.get_profile(PROFILE))
@given(data=text_cases("yaml"))
def test_map_yaml(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("m") / "map.yaml"
    path.write_bytes(data)
    only_floorscan_errors(read_map_yaml, path)


@settings(settings.get_profile(PROFILE), max_examples=10 if PROFILE == "ci" else 300)
@given(data=st.binary(max_size=2000), ros1=st.booleans())
def test_bags(tmp_path_factory, data, ros1):
    from floorscan.formats.rosbag import iter_bag_images, read_bag_odometry

    folder = tmp_path_factory.mktemp("b")
    if ros1:
        path = folder / "b.bag"
        path.write_bytes(b"#ROSBAG V2.0\n" + data)
    else:
        path = folder / "bag"
        path.mkdir()
        (path / "metadata.yaml").write_bytes(data[:200])
        (path / "bag_0.mcap").write_bytes(data[200:])
    only_floorscan_errors(lambda: read_bag_odometry(path, odom_topic="/odom"))
    only_floorscan_errors(lambda: list(iter_bag_images(path, image_topic="/camera/image_raw")))
