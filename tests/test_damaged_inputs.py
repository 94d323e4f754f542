"""Every command, every kind of file it reads, damaged three ways (empty, random bytes, cut in
half): the command ends with a one-line error and exit status 1 (a FloorscanError), never an
internal error (5), a traceback, or a silent success. A run's damaged frame is the one
exception by design: the frame is skipped and counted (`skipped_unreadable`), the run goes on.
"""

from __future__ import annotations

import gzip
import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from floorscan import OccupancyGrid
from floorscan.cli import main
from floorscan.formats.image_io import write_png
from PIL import Image
from synthetic_dataset import camera_table, make_dataset

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

DAMAGES = ("empty", "garbage", "truncated")


def damage(path: Path, how: str) -> None:
    data = path.read_bytes()
    if how == "empty":
        path.write_bytes(b"")
    elif how == "garbage":
        path.write_bytes(np.random.default_rng(len(data)).integers(0, 256, 777, np.uint8).tobytes())
    else:
        path.write_bytes(data[: len(data) // 2])


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> Path:
    """Valid files of every kind the commands read."""
    d = tmp_path_factory.mktemp("valid")
    make_dataset(d / "room", n=4)
    camera_table().save(d / "table.json")
    write_png(d / "frame.png", np.full((48, 64), 90, np.uint8))
    texture = np.random.default_rng(5).integers(0, 255, (48, 64), np.uint8)
    Image.fromarray(texture).save(d / "frame.jpg", quality=90)
    write_png(d / "frame16.png", texture.astype(np.uint16) * 257)
    (d / "config.toml").write_text('[ranger]\nthreshold = 12.0\n[outputs]\noverlay = "none"\n')
    assert main(["sim", "--world", "room", "--seconds", "0.3", "-o", str(d / "sim")]) == 0
    cal = d / "sim" / "calibration"
    calibrate = ["calibrate", str(cal / "pattern.png"), "--pattern", str(cal / "pattern.toml")]
    assert main([*calibrate, "-o", str(d / "sim_table.json")]) == 0  # once, not per case
    # the simulated camera's intrinsics as OpenCV's FileStorage and ROS camera_info write them
    lens = json.loads((d / "sim" / "truth" / "camera.json").read_text())["lens"]
    k = [[lens["fx"], 0.0, lens["cx"]], [0.0, lens["fy"], lens["cy"]], [0.0, 0.0, 1.0]]
    dist = [lens["k1"], lens["k2"], lens["k3"], lens["k4"]]
    import cv2

    fs = cv2.FileStorage(str(d / "intrinsics.yml"), cv2.FILE_STORAGE_WRITE)
    fs.write("camera_matrix", np.array(k))
    fs.write("distortion_coefficients", np.array(dist))
    fs.write("distortion_model", "fisheye")
    fs.release()
    (d / "camera_info.yaml").write_text(
        "image_width: 320\nimage_height: 240\ndistortion_model: equidistant\n"
        f"camera_matrix:\n  rows: 3\n  cols: 3\n  data: {sum(k, [])}\n"
        f"distortion_coefficients:\n  rows: 1\n  cols: 4\n  data: {dist}\n"
    )
    grid = OccupancyGrid(keep_evidence=True)
    grid.insert_laser(np.array([1.0, 1.5, 2.0]), pose=(0.0, 0.0, 0.0), angle_min=-0.2,
                      angle_increment=0.2, range_max_m=5.0)  # fmt: skip
    grid.save(d / "map.yaml")
    grid.evidence(name="m").save(d / "map.evidence.npz")
    lines = "".join(
        f"FLASER 3 1.0 1.5 2.0 {0.1 * k} 0 0 {0.1 * k} 0 0 {k}.0 h {k}.0\n" for k in range(20)
    )
    (d / "log.gz").write_bytes(gzip.compress(lines.encode()))
    shutil.copy(Path(__file__).resolve().parents[1] / "bench/worlds/study.toml", d / "world.toml")
    # a ROS 2 bag of the dataset's frames, and a video of them (what `run` also reads)
    from floorscan.formats.dataset import read_images_txt
    from floorscan.formats.image_io import read_grey
    from floorscan.formats.rosbag import rosbags_installed, write_image_odometry_bag
    from floorscan.formats.trajectory import read_tum

    frames = [(e.timestamp, read_grey(e.path)) for e in read_images_txt(d / "room")]
    if rosbags_installed():
        write_image_odometry_bag(d / "bag", frames, read_tum(d / "room" / "odometry.txt"))
        write_image_odometry_bag(
            d / "bag1.bag", frames, read_tum(d / "room" / "odometry.txt"), ros_version=1
        )
        write_image_odometry_bag(
            d / "bag_png", frames, read_tum(d / "room" / "odometry.txt"), compressed=True
        )
    (d / "labels.csv").write_text("image,column,row\n0,40,60.5\n1,90,61.0\n")
    import cv2

    h, w = frames[0][1].shape
    video = cv2.VideoWriter(str(d / "video.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (w, h))
    for _, g in frames * 3:
        video.write(cv2.cvtColor(g, cv2.COLOR_GRAY2BGR))
    video.release()
    (d / "fleet.toml").write_text(
        f'table = "{d / "table.json"}"\n[[recording]]\ninput = "{d / "room"}"\n'
    )
    return d


def target_file(d: Path, target: str) -> Path:
    """The file of ``target`` in the copy ``d``: a bag's ``storage`` is whichever file its
    writer made beside ``metadata.yaml`` (its name and kind are the writer's)."""
    if target.endswith("/storage"):
        folder = d / target.split("/")[0]
        return next(p for p in folder.iterdir() if p.name != "metadata.yaml")
    return d / target


def _valid_toml(path: Path) -> bool:
    try:
        tomllib.loads(path.read_text())
        return True
    except (ValueError, UnicodeDecodeError):
        return False


def case_room(d, f):
    return ["run", str(d / "room"), "--table", str(d / "table.json"), "-o", str(d / "out")]


# command line builder, the file (relative to the copy of `base`) to damage, what must happen
CASES = {
    "scan-table": (
        lambda d: ["scan", "--table", str(d / "table.json"), str(d / "frame.png"), "-o", str(d / "s.csv")],
        "table.json",
    ),
    "scan-image": (
        lambda d: ["scan", "--table", str(d / "table.json"), str(d / "frame.png"), "-o", str(d / "s.csv")],
        "frame.png",
    ),
    "scan-jpeg": (
        lambda d: ["scan", "--table", str(d / "table.json"), str(d / "frame.jpg"), "-o", str(d / "s.csv")],
        "frame.jpg",
    ),
    "scan-png16": (
        lambda d: ["scan", "--table", str(d / "table.json"), str(d / "frame16.png"), "-o", str(d / "s.csv")],
        "frame16.png",
    ),
    "scan-config": (
        lambda d: ["scan", "--table", str(d / "table.json"), "--config", str(d / "config.toml"),
                   str(d / "frame.png"), "-o", str(d / "s.csv")],
        "config.toml",
    ),
    "overlay-image": (
        lambda d: ["overlay", "--table", str(d / "table.json"), str(d / "frame.png"), "-o", str(d / "o.png")],
        "frame.png",
    ),
    "run-table": (lambda d: case_room(d, None), "table.json"),
    "run-config": (lambda d: case_room(d, None) + ["--config", str(d / "config.toml")], "config.toml"),
    "run-images-txt": (lambda d: case_room(d, None), "room/images.txt"),
    "run-odometry": (lambda d: case_room(d, None), "room/odometry.txt"),
    "run-rig": (lambda d: case_room(d, None), "room/rig.toml"),
    "run-frame": (lambda d: case_room(d, None), "room/images/000001.png"),
    "calibrate-image": (
        lambda d: ["calibrate", str(d / "sim/calibration/pattern.png"), "--pattern",
                   str(d / "sim/calibration/pattern.toml"), "-o", str(d / "t.json")],
        "sim/calibration/pattern.png",
    ),
    "calibrate-pattern": (
        lambda d: ["calibrate", str(d / "sim/calibration/pattern.png"), "--pattern",
                   str(d / "sim/calibration/pattern.toml"), "-o", str(d / "t.json")],
        "sim/calibration/pattern.toml",
    ),
    "calibrate-opencv-intrinsics": (
        lambda d: ["calibrate", str(d / "sim/calibration/pattern.png"), "--pattern",
                   str(d / "sim/calibration/pattern.toml"), "--intrinsics", str(d / "intrinsics.yml"),
                   "-o", str(d / "t.json")],
        "intrinsics.yml",
    ),
    "calibrate-ros-intrinsics": (
        lambda d: ["calibrate", str(d / "sim/calibration/pattern.png"), "--pattern",
                   str(d / "sim/calibration/pattern.toml"), "--intrinsics", str(d / "camera_info.yaml"),
                   "-o", str(d / "t.json")],
        "camera_info.yaml",
    ),
    "map-log": (lambda d: ["map-log", str(d / "log.gz"), "-o", str(d / "m/m.yaml")], "log.gz"),
    "merge-evidence": (
        lambda d: ["merge", str(d / "map.evidence.npz"), "-o", str(d / "merged")],
        "map.evidence.npz",
    ),
    "sim-world": (lambda d: ["sim", "--world", str(d / "world.toml"), "--seconds", "0.2",
                             "-o", str(d / "s2")], "world.toml"),
    "config-check": (lambda d: ["config", "--check", str(d / "config.toml")], "config.toml"),
    "fleet-spec": (lambda d: ["fleet", "--fleet", str(d / "fleet.toml"), "-o", str(d / "f")], "fleet.toml"),
    "run-bag-metadata": (lambda d: ["run", str(d / "bag"), "--table", str(d / "table.json"),
                                    "-o", str(d / "out")], "bag/metadata.yaml"),
    "run-bag-storage": (lambda d: ["run", str(d / "bag"), "--table", str(d / "table.json"),
                                   "-o", str(d / "out")], "bag/storage"),
    "run-bag-png": (lambda d: ["run", str(d / "bag_png"), "--table", str(d / "table.json"),
                                "-o", str(d / "out")], "bag_png/storage"),
    "run-bag1": (lambda d: ["run", str(d / "bag1.bag"), "--table", str(d / "table.json"),
                             "-o", str(d / "out")], "bag1.bag"),
    "tune-truth": (lambda d: ["tune", str(d / "sim"), "--table", str(d / "sim_table.json"),
                              "-o", str(d / "t.toml"), "--half-widths", "2",
                              "--thresholds", "10:12:1", "--frames", "3"], "sim/truth/columns.csv"),
    "tune-labels": (lambda d: ["tune", str(d / "room"), "--labels", str(d / "labels.csv"), "--table",
                               str(d / "table.json"), "-o", str(d / "t.toml"), "--half-widths", "2",
                               "--thresholds", "10:12:1"], "labels.csv"),
    "eval-truth-map": (lambda d: ["eval", str(d / "sim"), "--table", str(d / "sim_table.json"),
                                  "-o", str(d / "ev")], "sim/truth/map.yaml"),
    "run-video": (lambda d: ["run", str(d / "video.avi"), "--table", str(d / "table.json"),
                             "-o", str(d / "out")], "video.avi"),
}  # fmt: skip


@pytest.mark.parametrize("how", DAMAGES)
@pytest.mark.parametrize("name", sorted(CASES))
def test_a_damaged_input_ends_in_one_line(base, tmp_path, capsys, name, how):
    build, target = CASES[name]
    if name.startswith("run-bag") and not (base / "bag").is_dir():
        pytest.skip("rosbags is not installed: no bag to damage")
    d = tmp_path / "d"
    shutil.copytree(base, d)
    damage(target_file(d, target), how)
    capsys.readouterr()
    rc = main(build(d))
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip() and "warning" not in ln.lower()]
    assert "Traceback" not in err and "internal error" not in err, err
    if name == "run-video" and how == "truncated" and rc == 0:
        # a video cut short plays the frames before the cut: they are mapped
        counts = json.loads((d / "out" / "summary.json").read_text())["counts"]
        assert counts["frames_mapped"] >= 1, counts
        return
    if name == "run-frame" or (name == "run-images-txt" and rc == 0):
        # a damaged frame (or a listing line cut in half, naming no file) is skipped and
        # counted; the run goes on with the others
        assert rc == 0, err
        counts = json.loads((d / "out" / "summary.json").read_text())["counts"]
        assert counts["skipped_unreadable"] == 1 and counts["frames_mapped"] >= 1, counts
        return
    if target.endswith(".toml") and _valid_toml(d / target):
        # what is left of a TOML file may be a valid one (an empty file: every default)
        assert rc in (0, 1), (rc, err)
        return
    if name == "fleet-spec" and how == "empty":
        # an empty fleet file names no recording: the one-line error says so
        assert rc == 1 and "recording" in err, err
        return
    assert rc == 1, (rc, err)
    assert 1 <= len([ln for ln in lines if "error" in ln]) <= 1, err
