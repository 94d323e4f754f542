"""The rule a default must pass (issue 39): the configured ranger (its kind and every option at
its default) is no worse than the edge ranger at the same options, nor than the paper's own
edge filter (`PAPER_EDGE`: so a changed option default is held to it too), on every real set
with truth in ../shared/data, grey and colour, and on the quick simulated suite. Real frames
decide: this test computes the scoreboard of ``floorscan eval --real`` and fails when the
default loses anywhere. Skips when the data is absent."""

from __future__ import annotations

import pytest
from conftest import shared_data_dir
from floorscan.evaluation.real_sets import (
    PAPER,
    PAPER_EDGE,
    default_losses,
    find_real_sets,
    score_real_sets,
)
from floorscan.evaluation.runner import run_suite
from floorscan.evaluation.scenarios import quick_suite
from floorscan.pipeline.config import Config

DATA = shared_data_dir()
pytestmark = pytest.mark.skipif(
    not (DATA / "floors" / "masks").is_dir(), reason=f"real floor data not found under {DATA}"
)


def test_the_default_ranger_never_loses_to_the_edge_ranger_on_a_real_set():
    cfg = Config()
    kinds = tuple(dict.fromkeys(("edge", cfg.ranger.kind)))
    res = score_real_sets(DATA, cfg, kinds=kinds)
    assert "floors" in res["sets"], [s.name for s in find_real_sets(DATA)]
    losses = default_losses(res)
    assert not losses, "the default loses to the edge ranger: " + "; ".join(losses)


def test_the_default_ranger_never_loses_to_the_edge_ranger_on_the_quick_suite():
    cfg = Config()
    if cfg.ranger.kind == "edge":
        pytest.skip("the default is the edge ranger itself")

    def wrong(c):
        recs = run_suite(quick_suite(seconds=4.0), c, threads=2)
        return sum(
            r["metrics"]["boundary"]["error_rate"] * r["metrics"]["boundary"]["columns"]
            for r in recs
        )

    edge = wrong(cfg.with_overrides({"ranger.kind": "edge"}))
    assert wrong(cfg) <= edge


def test_the_default_ranger_never_loses_to_the_papers_own_filter():
    cfg = Config()
    res = score_real_sets(DATA, cfg, kinds=(cfg.ranger.kind,), paper=True)
    assert PAPER in res["sets"]["floors"]["scores"]["grey"]
    losses = default_losses(res)
    assert not losses, "the default loses to the paper's filter: " + "; ".join(losses)

    def suite_wrong(c):
        recs = run_suite(quick_suite(seconds=4.0), c, threads=2)
        return sum(
            r["metrics"]["boundary"]["error_rate"] * r["metrics"]["boundary"]["columns"]
            for r in recs
        )

    assert suite_wrong(cfg) <= suite_wrong(cfg.with_overrides(PAPER_EDGE))
