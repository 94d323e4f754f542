"""``floorscan calibrate``: files in, table, overlay and report out; clear errors."""

from __future__ import annotations

import json

import pytest
from floorscan import GroundTable
from floorscan.cli import main
from floorscan.formats.image_io import write_png
from floorscan.sim import Camera, render_calibration


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    folder = tmp_path_factory.mktemp("calibration")
    image, pattern = render_calibration(Camera(), kind="checkerboard")
    write_png(folder / "pattern.png", image)
    pattern.save(folder / "pattern.toml")
    return folder


def test_calibrate_writes_table_overlay_and_report(scene, tmp_path, capsys):
    code = main(
        [
            "calibrate",
            str(scene / "pattern.png"),
            "-o",
            str(tmp_path / "table.json"),
            "--overlay",
            str(tmp_path / "overlay.png"),
            "--report",
            str(tmp_path / "report.json"),
            "--spacing",
            "4",
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "63/63 points" in out and len(out.strip().splitlines()) == 1
    table = GroundTable.load(tmp_path / "table.json")
    assert table.spacing_px == 4 and (table.image_width, table.image_height) == (320, 240)
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["points_found"] == 63 and report["spacing_px"] == 4
    assert (tmp_path / "overlay.png").stat().st_size > 1000


def test_calibrate_errors_are_reported_not_raised(scene, tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('kind = "checkerboard"\ninner_corners = [9, 7]\nnear_left = [0.2, 0.4]\n')
    code = main(
        [
            "calibrate",
            str(scene / "pattern.png"),
            "--pattern",
            str(bad),
            "-o",
            str(tmp_path / "t.json"),
        ]
    )
    assert code == 1
    assert "missing key `square`" in capsys.readouterr().err
    code = main(["calibrate", str(tmp_path / "none.png"), "-o", str(tmp_path / "t.json")])
    assert code == 1
    assert "not found" in capsys.readouterr().err
    assert not (tmp_path / "t.json").exists()


def test_calibrate_reads_the_config_and_flags_win(scene, tmp_path):
    config = tmp_path / "robot.toml"
    config.write_text('[calibration]\nspacing_px = 8\nmax_range_m = 2.0\ncoverage = "pattern"\n')
    image = str(scene / "pattern.png")
    assert main(["calibrate", image, "-o", str(tmp_path / "a.json"), "--config", str(config)]) == 0
    a = GroundTable.load(tmp_path / "a.json")
    assert a.spacing_px == 8
    assert a.metadata["calibration"]["coverage"] == "pattern"
    out = tmp_path / "b.json"
    args = ["calibrate", image, "-o", str(out), "--config", str(config), "--spacing", "4"]
    assert main(args) == 0
    b = GroundTable.load(out)
    assert b.spacing_px == 4 and b.metadata["calibration"]["coverage"] == "pattern"
    # a bad value in the file is refused before any work, naming the key
    config.write_text("[calibration]\nmax_error_fraction = -1\n")
    assert main(["calibrate", image, "-o", str(tmp_path / "c.json"), "--config", str(config)]) != 0
    assert not (tmp_path / "c.json").exists()
