"""Real-floor evaluation (floorscan.evaluation.floor_masks, floor_cv, ``floorscan eval
--floors``): the per-column truth against a brute-force scan of synthetic masks, the row
tolerance, the folder format, and cross-validation on a synthetic floor-mask folder."""

from __future__ import annotations

import json

import floorscan as fs
import numpy as np
import pytest
from floorscan.cli import main as cli_main
from floorscan.evaluation.floor_cv import cross_validate
from floorscan.evaluation.floor_eval import floor_ranger_factory
from floorscan.evaluation.floor_masks import (
    floor_mask_truth,
    list_floor_frames,
    load_floor_frames,
    row_tolerance_px,
    score_floor_frames,
    summarise_floor_scores,
    wrong_columns,
)
from floorscan.pipeline.config import Config
from PIL import Image


def brute_force_truth(mask):
    """The README's rule, one column and one pixel at a time."""
    h, w = mask.shape
    out = []
    for u in range(w):
        if not mask[h - 1, u]:
            out.append(("too_close", None))
            continue
        found = None
        for v in range(h - 1, -1, -1):
            if v - 2 >= 0 and not mask[v, u] and not mask[v - 1, u] and not mask[v - 2, u]:
                found = v
                break
        out.append(("boundary", found) if found is not None else ("no_boundary", None))
    return out


@pytest.mark.parametrize("seed", range(20))
def test_truth_matches_brute_force_on_random_masks(seed):
    rng = np.random.default_rng(seed)
    h, w = int(rng.integers(4, 40)), int(rng.integers(1, 30))
    mask = rng.random((h, w)) < rng.uniform(0.3, 0.95)
    status, rows = floor_mask_truth(mask)
    names = {0: "boundary", 1: "no_boundary", 2: "too_close"}
    for u, (s, v) in enumerate(brute_force_truth(mask)):
        assert names[int(status[u])] == s, (u, mask[:, u])
        if v is None:
            assert np.isnan(rows[u])
        else:
            assert rows[u] == v


def test_tolerance_and_wrong_columns():
    assert row_tolerance_px(100) == 3.0
    assert row_tolerance_px(1138) == pytest.approx(14.225)
    true_s = np.array([0, 0, 1, 2, 0])
    true_r = np.array([50.0, 50.0, np.nan, np.nan, 10.0])
    s = np.array([0, 0, 1, 0, 3])
    r = np.array([53.0, 46.9, 0.0, 90.0, np.nan])
    np.testing.assert_array_equal(
        wrong_columns(s, r, true_s, true_r, 100), [False, True, False, True, True]
    )
    with pytest.raises(fs.DatasetError):
        floor_mask_truth(np.zeros(5))


def write_floor_folder(root, clips=("a_01", "b_01", "c_01"), frames=2, seed=0):
    """Frames of a plain brownish floor under a blue wall whose base row is known per clip;
    masks drawn from the same geometry."""
    rng = np.random.default_rng(seed)
    (root / "images").mkdir(parents=True)
    (root / "masks").mkdir()
    h, w = 60, 80
    for ci, clip in enumerate(clips):
        for f in range(frames):
            base = 20 + 5 * ci + f
            img = np.zeros((h, w, 3), np.uint8)
            img[:] = (140, 120, 90)
            img[:base] = (30, 60, 170)
            img = np.clip(img + rng.integers(-4, 5, img.shape), 0, 255).astype(np.uint8)
            mask = np.full((h, w), 255, np.uint8)
            mask[:base] = 0
            stem = f"{clip}_f{f:06d}"
            Image.fromarray(img).save(root / "images" / f"{stem}.jpg", quality=95)
            Image.fromarray(mask).save(root / "masks" / f"{stem}.png")
    (root / "floor_types.csv").write_text("clip,floor_type\na_01,oak\n")
    return root


def test_a_synthetic_folder_scores_and_cross_validates(tmp_path):
    root = write_floor_folder(tmp_path / "floors")
    frames = list_floor_frames(root)
    assert [f.clip for f in frames] == ["a_01"] * 2 + ["b_01"] * 2 + ["c_01"] * 2
    loaded = load_floor_frames(frames)
    per_clip = score_floor_frames(loaded, floor_ranger_factory(Config(), "appearance"))
    summary = summarise_floor_scores(per_clip, {"a_01": "oak"})
    assert summary["overall"]["error_rate"] == 0.0
    assert summary["clips"]["a_01"]["floor_type"] == "oak"
    assert summary["overall"]["truth_boundary"] == 6 * 64
    # Cross-validation: an absurd option value loses to a sane one on the training clips.
    cv = cross_validate(
        loaded,
        lambda o: floor_ranger_factory(Config().with_overrides(o), "appearance"),
        {"appearance.min_run": [1, 40]},
    )
    assert cv["error_rate"] == 0.0
    assert all(h["options"]["appearance.min_run"] == 1 for h in cv["held_out"].values())


def test_the_bottom_trim_diagnostic_and_missing_parts(tmp_path):
    root = write_floor_folder(tmp_path / "floors", clips=("a_01",), frames=1)
    m = root / "masks" / "a_01_f000000.png"
    arr = np.asarray(Image.open(m)).copy()
    arr[-1] = 0  # a lost bottom row: the rule says too_close
    Image.fromarray(arr).save(m)
    frames = list_floor_frames(root)
    assert (load_floor_frames(frames)[0].true_status == 2).all()
    assert (load_floor_frames(frames, trim_mask_bottom=1)[0].true_status == 0).all()
    m.unlink()
    with pytest.raises(fs.DatasetError):
        list_floor_frames(root)
    with pytest.raises(fs.DatasetError):
        list_floor_frames(tmp_path / "nowhere")


def test_cli_eval_floors(tmp_path, capsys):
    root = write_floor_folder(tmp_path / "floors")
    out = tmp_path / "out"
    rc = cli_main(["eval", "--floors", str(root), "--cross-validate", "-o", str(out)])
    assert rc == 0
    text = capsys.readouterr().out
    for kind in ("edge", "appearance", "fused"):
        assert f"{kind} ranger" in text
    res = json.loads((out / "floors.json").read_text())
    assert res["appearance"]["at_config"]["overall"]["error_rate"] == 0.0
    assert "cross_validated" in res["fused"]
