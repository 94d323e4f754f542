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
