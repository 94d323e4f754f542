"""floorscan tune: the grid search finds the optimum computed by hand on synthetic images, and
the label-free texture-noise estimate matches the filter's noise computed analytically."""

from __future__ import annotations

import numpy as np
import pytest
import tomllib
from conftest import affine_table
from floorscan.cli import main
from floorscan.errors import FileFormatError
from floorscan.evaluation.tune import TuneSet, read_labels_csv, texture_noise, tune
from floorscan.formats.image_io import write_png

W, H = 64, 240
EDGE_ROW = 100  # rows < 100 are the obstacle (140), rows >= 100 the floor (100)
LINE_ROW = 200  # a one-pixel dark line on the floor (76)


def synthetic_image() -> np.ndarray:
    img = np.full((H, W), 100, np.uint8)
    img[:EDGE_ROW] = 140
    img[LINE_ROW] = 76
    return img


# By hand: the raw response is S = (sum of the d pixels above) - (sum of the d below) and a
# column fires when |S| > floor(2 d T). The step of 40 gives |S| = 40 d: it fires iff T < 20.
# The line of depth 24 gives |S| = 24 whatever d: it fires iff T < 12 / d. A column is right
# iff the line stays silent and the step fires: 12 / d <= T < 20. With integer T in 1..25:
# d = 1: T in 12..19; d = 2: 6..19; d = 4: 3..19 (the widest band). The rule takes the widest
# zero-error band's centre: d = 4, T = (3 + 19) / 2 = 11.
EXPECTED = (4, 11.0)


def tune_set(table):
    images = [synthetic_image() for _ in range(3)]
    status = np.zeros((3, W), np.int64)  # every column: boundary
    x, y = table.lookup(np.arange(W, dtype=float), np.full(W, EDGE_ROW - 0.5))
    points = np.stack([np.stack([x, y], axis=1)] * 3)
    labelled = np.zeros((3, W), bool)
    labelled[:, ::4] = True
    return TuneSet(images, status, points, labelled, table)


def test_tune_finds_the_optimum_computed_by_hand():
    table = affine_table(W, H, spacing=4)
    result = tune(
        tune_set(table),
        half_widths=[1, 2, 4],
        thresholds=list(range(1, 26)),
        refinements=["sub_pixel"],
    )
    assert (result.half_width, result.threshold) == EXPECTED
    assert result.error_rate == 0.0
    errors = result.errors["sub_pixel"]
    for d, lo in ((1, 12), (2, 6), (4, 3)):
        zero = [t for t, e in zip(result.thresholds, errors[d]) if e == 0.0]
        assert zero == [float(t) for t in range(lo, 20)]
        # Below the band the line fires (every column wrong); above it nothing fires.
        assert errors[d][0] == 1.0 and errors[d][-1] == 1.0


def test_tune_command_with_hand_labels_writes_the_config_and_plot(tmp_path):
    table = affine_table(W, H, spacing=4)
    ds = tmp_path / "ds"
    (ds / "images").mkdir(parents=True)
    lines = []
    for k in range(3):
        write_png(ds / "images" / f"{k:06d}.png", synthetic_image())
        lines.append(f"{0.1 * k:.6f} images/{k:06d}.png")
    (ds / "images.txt").write_text("\n".join(lines) + "\n")
    table.save(tmp_path / "table.json")
    labels = ["image,column,row"]
    for k in range(3):
        for u in range(0, W, 8):
            labels.append(f"images/{k:06d}.png,{u},{EDGE_ROW - 0.5}")
    (tmp_path / "labels.csv").write_text("\n".join(labels) + "\n")
    out = tmp_path / "tuned.toml"
    rc = main(
        [
            "tune", str(ds), "--labels", str(tmp_path / "labels.csv"),
            "--table", str(tmp_path / "table.json"), "-o", str(out),
            "--half-widths", "1,2,4", "--thresholds", "1:25:1", "--refine", "subpixel",
        ]
    )  # fmt: skip
    assert rc == 0
    ranger = tomllib.loads(out.read_text())["ranger"]
    assert (ranger["half_width_px"], ranger["threshold"]) == EXPECTED
    assert (tmp_path / "tune.png").stat().st_size > 1000
    assert (tmp_path / "tune.json").is_file()


def test_labels_csv_rejects_unknown_images_and_reads_no_boundary(tmp_path):
    table = affine_table(W, H, spacing=4)
    p = tmp_path / "l.csv"
    p.write_text("image,column,row\nimages/a.png,3,\n1,5,120.5\n")
    status, points, labelled = read_labels_csv(p, ["images/a.png", "images/b.png"], table)
    assert status[0, 3] == 1 and labelled[0, 3]  # no boundary
    assert status[1, 5] == 0 and np.allclose(points[1, 5], table.lookup(5.0, 120.5))
    assert labelled.sum() == 2
    p.write_text("image,column,row\nimages/zz.png,3,10\n")
    with pytest.raises(FileFormatError, match="unknown image"):
        read_labels_csv(p, ["images/a.png"], table)


@pytest.mark.parametrize("d", [2, 4])
def test_texture_noise_matches_the_filter_noise_of_white_noise(d):
    # R = (mean of d pixels above - mean of d below) / 2 over independent pixels of standard
    # deviation sigma has standard deviation sigma / sqrt(2 d).
    rng = np.random.default_rng(3)
    sigma = 6.0
    images = [np.clip(rng.normal(120, sigma, (H, W)), 0, 255) for _ in range(4)]
    est = texture_noise(images, half_width=d, columns=np.arange(W), bottom_margin=2)
    assert est == pytest.approx(sigma / np.sqrt(2 * d), rel=0.06)
