"""Simulated runs written as dataset folders (the public format of docs/dataset-format.md), read
back with floorscan's own readers and independent parsers; the calibration scene against its
pattern.toml; the `floorscan sim` command."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from floorscan import DatasetError
from floorscan.cli import main
from floorscan.formats.dataset import read_images_txt
from floorscan.formats.image_io import read_grey
from floorscan.formats.rig import Rig, read_rig
from floorscan.formats.trajectory import read_tum
from floorscan.sim import (
    CalibrationPattern,
    Camera,
    World,
    render_calibration,
    simulate_run,
    write_dataset,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    run = simulate_run(
        World.builtin("room"), camera=Camera(width=160, height=120), seconds=2.0, seed=4
    )
    folder = write_dataset(run, tmp_path_factory.mktemp("ds") / "room")
    return run, folder


def test_images_and_trajectories_read_back(dataset):
    run, folder = dataset
    entries = read_images_txt(folder)
    assert len(entries) == len(run) == 21
    assert [e.path.name for e in entries[:2]] == ["000000.png", "000001.png"]
    assert np.allclose([e.timestamp for e in entries], run.timestamps)
    for k in (0, 20):
        assert np.array_equal(read_grey(entries[k].path), run.images[k])
    for name, poses in (("groundtruth.txt", run.poses), ("odometry.txt", run.odometry)):
        traj = read_tum(folder / name)
        assert np.allclose(traj.timestamps, run.timestamps)
        assert np.allclose(traj.x, poses[:, 0], atol=1e-6) and np.allclose(
            traj.y, poses[:, 1], atol=1e-6
        )
        assert np.allclose(np.angle(np.exp(1j * (traj.yaw - poses[:, 2]))), 0, atol=1e-8)
        # TUM lines: 8 numbers, z = 0, a unit quaternion about z.
        rows = [
            ln.split() for ln in (folder / name).read_text().splitlines() if not ln.startswith("#")
        ]
        q = np.array(rows, dtype=float)
        assert q.shape == (21, 8) and np.all(q[:, 3:6] == 0)
        assert np.allclose(q[:, 6] ** 2 + q[:, 7] ** 2, 1.0)
    assert read_rig(folder / "rig.toml") == Rig(x=0.12, y=0.0, yaw=0.0, height=0.4)


def test_truth_folder(dataset):
    run, folder = dataset
    truth = folder / "truth"
    lines = (truth / "columns.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert header[:5] == ["timestamp", "frame", "column", "status", "row"]
    assert len(lines) == 1 + 21 * 160
    first = dict(zip(header, lines[1].split(",")))
    assert first["status"] == run.truth.status_names[0][0]
    assert float(first["frame"]) == 0 and int(first["column"]) == 0
    assert np.array_equal(read_grey(truth / "labels" / "000005.png"), run.labels[5])
    yaml = (truth / "map.yaml").read_text()
    assert "image: map.pgm" in yaml and "mode: trinary" in yaml
    assert (truth / "map.pgm").read_bytes().startswith(b"P5\n")
    cam = Camera.load(truth / "camera.json")
    assert cam.width == 160 and cam.lens == run.camera.lens and cam.mount == run.camera.mount
    assert World.load(truth / "world.toml").name == "room"
    frames = (truth / "frames.csv").read_text().splitlines()
    assert frames[0] == "frame,timestamp,x,y,yaw,exposure" and len(frames) == 22


def test_checkerboard_scene_matches_its_pattern_toml(dataset):
    run, folder = dataset
    spec = tomllib.loads((folder / "calibration" / "pattern.toml").read_text())
    assert (
        spec["kind"] == "checkerboard" and spec["inner_corners"] == [9, 7] and spec["square"] == 0.1
    )
    assert set(spec) == {"kind", "inner_corners", "square", "near_left", "yaw"}
    image = read_grey(folder / "calibration" / "pattern.png")
    cam = run.camera
    nl = np.array(spec["near_left"])
    yaw = spec["yaw"]
    away = np.array([math.cos(yaw), math.sin(yaw)])
    across = np.array([math.sin(yaw), -math.cos(yaw)])
    # The square whose corners are inner corners (i, j) and (i + 1, j + 1) is dark when
    # i + j is even... or odd: whichever, its colour alternates between neighbours.
    values = {}
    for i in range(-1, 9):
        for j in range(-1, 7):
            centre = nl + (i + 0.5) * 0.1 * across + (j + 0.5) * 0.1 * away
            u, v = cam.ground_to_pixel(*centre)
            values[i, j] = float(image[int(round(v)), int(round(u))])
    dark = {k for k, val in values.items() if val < 80}
    light = {k for k, val in values.items() if val > 150}
    assert len(dark) + len(light) == len(values)
    parity = {(i + j) % 2 for (i, j) in dark}
    assert len(parity) == 1 and {(i + j) % 2 for (i, j) in light} == {1 - parity.pop()}


def test_lines_scene_is_dark_at_its_crossings():
    cam = Camera()
    image, pattern = render_calibration(cam, kind="lines", seed=1)
    text = pattern.to_toml()
    spec = tomllib.loads(text)
    assert spec["kind"] == "lines" and spec["lines"] == [7, 9] and spec["spacing"] == 0.2
    assert spec["line_width"] == 0.02
    pts = pattern.points()
    assert pts.shape == (63, 2)
    assert np.allclose(pts[0], spec["near_left"])
    u, v = cam.ground_to_pixel(pts[:, 0], pts[:, 1])
    on = image[np.round(v).astype(int), np.round(u).astype(int)].astype(float)
    # Half-way between crossings: carpet.
    mid = (pts[:-1] + pts[1:]) / 2 + np.array([0.1 * 0.5, 0.0])
    mu, mv = cam.ground_to_pixel(mid[:, 0], mid[:, 1])
    off = image[np.round(mv).astype(int), np.round(mu).astype(int)].astype(float)
    assert np.median(on) < 0.6 * np.median(off)
    # The default pattern lies entirely inside the image.
    assert np.all((u > 0) & (u < 319) & (v > 0) & (v < 239))


def test_pattern_descriptions_are_validated():
    with pytest.raises(ValueError, match="kind"):
        CalibrationPattern(kind="dots", near_left=(0.5, 0.4))
    with pytest.raises(ValueError, match="square"):
        CalibrationPattern(kind="checkerboard", near_left=(0.5, 0.4), square=-1.0)


def test_existing_folders_are_not_overwritten_unless_asked(tmp_path):
    run = simulate_run(World.builtin("tiles"), camera=Camera(width=32, height=24), seconds=0.3)
    target = tmp_path / "ds"
    target.mkdir()
    (target / "keep.txt").write_text("x")
    with pytest.raises(DatasetError, match="not empty"):
        write_dataset(run, target, calibration=None)
    write_dataset(run, target, calibration=None, truth=False, overwrite=True)
    assert not (target / "keep.txt").exists() and not (target / "truth").exists()
    assert len(read_images_txt(target)) == 4
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_sim_command_writes_a_dataset(tmp_path, capsys):
    out = tmp_path / "corridor"
    code = main(
        [
            "sim",
            "--world",
            "corridor",
            "--seconds",
            "0.5",
            "--out",
            str(out),
            "--width",
            "64",
            "--height",
            "48",
            "--calibration",
            "lines",
        ]
    )
    assert code == 0
    assert len(read_images_txt(out)) == 6
    assert tomllib.loads((out / "calibration" / "pattern.toml").read_text())["kind"] == "lines"
    assert "simulated 6 frames" in capsys.readouterr().err
    assert (
        main(["sim", "--world", "nowhere.toml", "--seconds", "1", "--out", str(tmp_path / "x")])
        == 1
    )
