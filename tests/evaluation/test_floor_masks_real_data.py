"""The rangers on ../shared/data/floors (real frames with hand-drawn floor masks). Skips when
the data is absent. Checks the truth's documented shape and that the evaluation runs end to
end on every frame; the figures themselves are reported in EVALUATION.md, not asserted."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import shared_data_dir
from floorscan.evaluation.floor_eval import floor_ranger_factory
from floorscan.evaluation.floor_masks import (
    floor_types,
    list_floor_frames,
    load_floor_frames,
    score_floor_frames,
    summarise_floor_scores,
)
from floorscan.pipeline.config import Config

FLOORS = shared_data_dir() / "floors"
pytestmark = pytest.mark.skipif(
    not (FLOORS / "masks").is_dir(), reason=f"real floor data not found at {FLOORS}"
)


def test_every_frame_has_truth_for_every_column_and_the_rangers_score_it():
    frames = list_floor_frames(FLOORS)
    assert len(frames) == 54
    assert len({f.clip for f in frames}) == 6
    loaded = load_floor_frames(frames)
    for lf in loaded:
        h, w = lf.rgb.shape[:2]
        assert lf.true_status.shape == (w,)
        b = lf.true_status == 0
        assert np.all((lf.true_rows[b] >= 0) & (lf.true_rows[b] < h))
    types = floor_types(FLOORS)
    for kind in ("edge", "appearance"):
        s = summarise_floor_scores(
            score_floor_frames(loaded, floor_ranger_factory(Config(), kind)), types
        )
        assert s["overall"]["columns"] == 54 * 64
        assert 0.0 <= s["overall"]["error_rate"] <= 1.0
        assert set(s["floor_types"]) <= set(types.values()) | {"unknown"}
