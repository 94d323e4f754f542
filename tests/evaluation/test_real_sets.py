"""The real-set scoreboard (``floorscan eval --real``) on folders built here, where the truth
and the readings are known: every outcome is classified as a brute-force reading of the rule
would, sets are found by their layout, and the default rule flags a loss."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan.errors import DatasetError
from floorscan.evaluation.real_sets import (
    OUTCOMES,
    classify_columns,
    default_losses,
    find_real_sets,
    format_real_table,
    score_real_sets,
)
from floorscan.evaluation.scoring import BOUNDARY, INVALID, NO_BOUNDARY, TOO_CLOSE
from floorscan.pipeline.config import Config
from PIL import Image


def _brute(s, r, ts, tr, tol):
    if s == INVALID:
        return "invalid"
    if s == ts:
        return "row_off" if s == BOUNDARY and abs(r - tr) > tol else "right"
    return {
        BOUNDARY: "said_boundary",
        NO_BOUNDARY: "said_no_boundary",
        TOO_CLOSE: "said_too_close",
    }[s]


def test_classify_columns_matches_a_brute_force_reading_of_the_rule():
    rng = np.random.default_rng(3)
    n = 500
    s = rng.choice([BOUNDARY, NO_BOUNDARY, TOO_CLOSE, INVALID], n)
    ts = rng.choice([BOUNDARY, NO_BOUNDARY, TOO_CLOSE], n)
    r = np.where(s == BOUNDARY, rng.uniform(0, 100, n), np.nan)
    tr = np.where(ts == BOUNDARY, r + rng.uniform(-8, 8, n), np.nan)
    tr = np.where((ts == BOUNDARY) & np.isnan(tr), rng.uniform(0, 100, n), tr)
    got = classify_columns(s, r, ts, tr, 4.5)
    want = [_brute(*a, 4.5) for a in zip(s, r, ts, tr)]
    assert [OUTCOMES[i] for i in got] == want
    assert set(want) == set(OUTCOMES)


def _write_set(folder, *, step_row: int, frames: int = 3, noise: float = 2.0):
    """Frames of a bright floor below ``step_row`` and a dark wall above, with masks."""
    (folder / "images").mkdir(parents=True)
    (folder / "masks").mkdir()
    rng = np.random.default_rng(0)
    h, w = 120, 160
    for f in range(frames):
        img = np.full((h, w, 3), (60, 50, 40), np.float64)
        img[step_row:] = (200, 190, 170)
        img += rng.normal(0, noise, img.shape)
        mask = np.zeros((h, w), np.uint8)
        mask[step_row:] = 255
        stem = f"hall_f{f:06d}"
        Image.fromarray(np.clip(img, 0, 255).astype(np.uint8)).save(
            folder / "images" / f"{stem}.png"
        )
        Image.fromarray(mask).save(folder / "masks" / f"{stem}.png")


def test_sets_are_found_by_their_layout_and_named_by_the_readme(tmp_path):
    _write_set(tmp_path / "plain", step_row=70)
    _write_set(tmp_path / "more" / "tiles", step_row=50)
    (tmp_path / "empty" / "images").mkdir(parents=True)  # no masks/: not a set
    (tmp_path / "README.md").write_text("# data\n\n## plain/: a plain hall floor\n")
    sets = find_real_sets(tmp_path)
    assert [s.name for s in sets] == ["more/tiles", "plain"]
    assert sets[1].description == "a plain hall floor"
    with pytest.raises(DatasetError):
        find_real_sets(tmp_path / "empty")


def test_a_clean_step_is_scored_right_by_every_kind_and_the_counts_add_up(tmp_path):
    _write_set(tmp_path / "plain", step_row=70)
    res = score_real_sets(tmp_path, Config())
    scores = res["sets"]["plain"]["scores"]
    assert set(scores) == {"grey", "colour"}
    for by_kind in scores.values():
        assert set(by_kind) == {"edge", "appearance", "fused"}
        for s in by_kind.values():
            per_truth = s["by_truth"]
            assert sum(sum(t.values()) for t in per_truth.values()) == s["columns"]
            # the truth is a boundary in every column (mask step at row 70)
            assert sum(per_truth["boundary"].values()) == s["columns"]
            assert s["wrong"] == s["columns"] - per_truth["boundary"]["right"]
            assert s["wrong_strict"] >= s["wrong"]
    # the edge ranger places a clean step within the tolerance
    assert scores["grey"]["edge"]["error_rate"] == 0.0
    assert abs(scores["grey"]["edge"]["row_error_px"]["median"]) <= 1.0
    table = format_real_table(res)
    assert "plain, grey" in table and "no worse than the edge ranger" in table


def test_default_losses_flags_a_default_with_more_wrong_columns_than_edge():
    def score(wrong, strict):
        return {"wrong": wrong, "wrong_strict": strict}

    res = {
        "default_kind": "fused",
        "sets": {
            "a": {"scores": {"grey": {"edge": score(10, 20), "fused": score(10, 20)}}},
            "b": {"scores": {"colour": {"edge": score(10, 20), "fused": score(11, 19)}}},
        },
    }
    losses = default_losses(res)
    assert len(losses) == 1 and losses[0].startswith("b (colour): fused 11")
    res["default_kind"] = "edge"
    assert default_losses(res) == []
