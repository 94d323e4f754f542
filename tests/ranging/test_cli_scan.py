"""`floorscan scan` and `floorscan overlay` end to end."""

from __future__ import annotations

import numpy as np
from conftest import affine_table
from floorscan import VisualRanger, read_scans_csv
from floorscan.cli import main
from floorscan.formats.image_io import read_grey, write_png
from PIL import Image


def make_inputs(tmp_path):
    h, w = 48, 64
    table = affine_table(w, h)
    table.save(tmp_path / "table.json")
    v = np.arange(h)[:, None]
    paths = []
    for i, edge in enumerate((20, 25)):
        img = (np.where(v >= edge, 90, 180) * np.ones((1, w))).astype(np.uint8)
        paths.append(write_png(tmp_path / f"f{i}.png", img))
    return table, paths


def test_scan_command_writes_the_csv(tmp_path):
    _, paths = make_inputs(tmp_path)
    out = tmp_path / "scans.csv"
    rc = main(
        [
            "scan",
            "--table",
            str(tmp_path / "table.json"),
            *map(str, paths),
            "-o",
            str(out),
            "--columns",
            "8",
            "--threshold",
            "20",
        ]
    )
    assert rc == 0
    scans = read_scans_csv(out)
    assert [s.timestamp for s in scans] == [0.0, 1.0]
    np.testing.assert_array_equal(scans[0].rows, 19.5)
    np.testing.assert_array_equal(scans[1].rows, 24.5)


def test_scan_command_reads_dataset_timestamps(tmp_path):
    _, paths = make_inputs(tmp_path)
    ds = tmp_path / "ds"
    (ds / "images").mkdir(parents=True)
    for i, p in enumerate(paths):
        p.rename(ds / "images" / f"{i:06d}.png")
    (ds / "images.txt").write_text(
        "# timestamp path\n10.5 images/000000.png\n10.6 images/000001.png\n"
    )
    out = tmp_path / "scans.csv"
    assert main(["scan", "--table", str(tmp_path / "table.json"), str(ds), "-o", str(out)]) == 0
    assert [s.timestamp for s in read_scans_csv(out)] == [10.5, 10.6]


def test_overlay_command_draws_on_the_image(tmp_path):
    _, paths = make_inputs(tmp_path)
    out = tmp_path / "overlay.png"
    assert (
        main(
            [
                "overlay",
                "--table",
                str(tmp_path / "table.json"),
                str(paths[0]),
                "-o",
                str(out),
                "--columns",
                "8",
            ]
        )
        == 0
    )

    rgb = np.asarray(Image.open(out))
    assert rgb.shape == (48, 64, 3)
    # Green circles were drawn near the boundary row 19.5 and nowhere near the bottom.
    green = (rgb[..., 1] > 200) & (rgb[..., 0] < 100)
    rows = np.nonzero(green)[0]
    assert rows.size > 0 and rows.min() >= 15 and rows.max() <= 24


def test_bad_inputs_exit_with_a_message(tmp_path, capsys):
    _, paths = make_inputs(tmp_path)
    (tmp_path / "broken.png").write_bytes(b"not a png")
    rc = main(
        [
            "scan",
            "--table",
            str(tmp_path / "table.json"),
            str(tmp_path / "broken.png"),
            "-o",
            str(tmp_path / "s.csv"),
        ]
    )
    assert rc == 1
    assert "cannot read image" in capsys.readouterr().err
    rc = main(
        [
            "scan",
            "--table",
            str(tmp_path / "nope.json"),
            str(paths[0]),
            "-o",
            str(tmp_path / "s.csv"),
        ]
    )
    assert rc == 1
    assert read_grey(paths[0]).shape == (48, 64)


def test_a_truncated_image_is_an_error_unless_lenient(tmp_path, capsys):
    """A JPEG cut short: `scan` refuses it in one line; `--lenient` ranges what it holds (the
    rows it decodes are the intact file's rows) and says so."""
    from floorscan.formats.image_io import read_grey

    rng = np.random.default_rng(4)
    grey = (rng.random((48, 64)) * 255).astype(np.uint8)
    Image.fromarray(grey).save(tmp_path / "whole.jpg", quality=90)
    data = (tmp_path / "whole.jpg").read_bytes()
    (tmp_path / "cut.jpg").write_bytes(data[: len(data) * 2 // 3])
    affine_table(width=64, height=48).save(tmp_path / "t.json")
    args = ["scan", "--table", str(tmp_path / "t.json"), str(tmp_path / "cut.jpg")]
    assert main([*args, "-o", str(tmp_path / "a.csv")]) == 1
    assert "truncated" in capsys.readouterr().err
    assert main([*args, "-o", str(tmp_path / "b.csv"), "--lenient"]) == 0
    assert "warning" in capsys.readouterr().err
    whole, cut = read_grey(tmp_path / "whole.jpg"), read_grey(tmp_path / "cut.jpg", lenient=True)
    assert cut.shape == whole.shape
    assert np.array_equal(cut[:8], whole[:8])  # the first MCU row decoded as in the whole file


def grout_then_obstacle(h: int = 48, w: int = 64) -> np.ndarray:
    """Floor (150) from the bottom, a 2-row dark grout line (60) at rows 30-31, floor again,
    a dark obstacle (60) from row 10 up: its base lies at row 10.5, the line's lower side at
    31.5 (the affine table: 1 cm of floor a row, so the line is 2 cm wide)."""
    v = np.arange(h)[:, None]
    img = np.where((v <= 10) | ((v >= 30) & (v <= 31)), 60, 150)
    return (img * np.ones((1, w))).astype(np.uint8)


def test_floor_lines_from_the_config_pass_a_grout_line_in_scan_and_the_api(tmp_path):
    table = affine_table()
    table.save(tmp_path / "table.json")
    path = write_png(tmp_path / "f.png", grout_then_obstacle())
    rows = {}
    for name, width in (("off", 0.0), ("lines", 0.02)):
        cfg = tmp_path / f"{name}.toml"
        cfg.write_text(
            f"[ranger]\nfloor_line_width_m = {width}\nnoise_multiple = 0\ncontrast = 0\n"
        )
        out = tmp_path / f"{name}.csv"
        args = ["scan", "--table", str(tmp_path / "table.json"), str(path), "-o", str(out)]
        assert main([*args, "--columns", "8", "--threshold", "10", "--config", str(cfg)]) == 0
        rows[name] = read_scans_csv(out)[0].rows
    # the paper's first edge is the grout line; passing lines up to 2 cm finds the obstacle
    np.testing.assert_array_equal(rows["off"], 31.5)
    np.testing.assert_array_equal(rows["lines"], 10.5)
    # the Python API takes the option as a keyword, with the same result
    scan = VisualRanger(
        table, columns=8, threshold=10, noise_multiple=0, contrast=0, floor_line_width_m=0.02
    ).scan(grout_then_obstacle())
    np.testing.assert_array_equal(scan.rows, 10.5)
