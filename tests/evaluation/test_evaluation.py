"""floorscan eval: the quick suite on a reduced scenario produces a table that agrees with its
JSON and whose group figures follow from the per-scenario ones; a dataset with truth is scored
as the scoring functions score it directly."""

from __future__ import annotations

import json

import pytest
from floorscan.cli import main
from floorscan.errors import OptionError
from floorscan.evaluation.scenarios import (
    FAST_SPEED_MPS,
    TEXTURED_WORLDS,
    Scenario,
    full_suite,
    quick_suite,
    with_lighting,
)


def _table_rows(md: str, section: str):
    block = md.split(section, 1)[1].split("\n## ", 1)[0]
    rows = [line for line in block.splitlines() if line.startswith("| ")][1:]
    return [[c.strip() for c in r.strip("|").split("|")] for r in rows]


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("eval")
    assert main(["eval", "--quick", "--seconds", "2", "-o", str(out)]) == 0
    return out, (out / "report.md").read_text(), json.loads((out / "report.json").read_text())


def test_quick_table_has_one_row_per_scenario_matching_the_json(quick_report):
    _, md, doc = quick_report
    names = [s.name for s in quick_suite(seconds=2)]
    rows = _table_rows(md, "## Per scenario")
    assert [r[0] for r in rows] == names
    assert [s["scenario"]["name"] for s in doc["scenarios"]] == names
    for row, s in zip(rows, doc["scenarios"]):
        m = s["metrics"]
        assert row[1] == str(m["frames"]) == "21"
        assert row[2] == f"{100 * m['boundary']['error_rate']:.1f}"
        # every frame scores the same columns, the default placement (no 3 cm obstacle at 1 m
        # between two): denser than the old 64 on the simulator's 136-degree camera
        n = m["boundary"]["columns"]
        assert n % 21 == 0 and 64 < n // 21 <= 320
        agr = m["map"]["true_poses"]["agreement"]
        assert row[5].endswith(f"{100 * agr:.1f}") and 0.0 <= agr <= 1.0


def test_group_figures_pool_the_scenarios(quick_report):
    _, md, doc = quick_report
    by_group = {}
    for s in doc["scenarios"]:
        by_group.setdefault(s["scenario"]["group"], []).append(s["metrics"])
    assert set(doc["groups"]) == set(by_group) == {"carpet", "overhanging table"}
    for group, ms in by_group.items():
        g = doc["groups"][group]
        cols = sum(m["boundary"]["columns"] for m in ms)
        wrong = sum(m["boundary"]["columns"] * m["boundary"]["error_rate"] for m in ms)
        assert g["boundary"]["columns"] == cols
        assert g["boundary"]["error_rate"] == pytest.approx(wrong / cols)
        assert g["frames"] == sum(m["frames"] for m in ms)
        for key in ("reliable_local_map", "reliable_avoidance_map"):
            views = [f for m in ms for f in m[key]["frames_per_view"]]
            assert g[key]["frames_per_view"] == views
            right = [f for m in ms for f in m[key]["frames_ranger_right"]]
            assert g[key]["frames_ranger_right"] == right
            # the ranger-right views are a subset of the views, in order
            it = iter(views)
            assert all(any(f == v for v in it) for f in right)
            assert all(f is None or 1 <= f <= g[key]["max_frames_tried"] for f in views)
    group_rows = _table_rows(md, "## Per world group")
    assert [r[0] for r in group_rows] == ["carpet", "overhanging table"]
    assert "## Goals" in md
    # Every band's point count adds up to the boundary points scored in both.
    b = doc["groups"]["carpet"]["boundary"]
    assert sum(v["points"] for v in b["by_range"].values()) <= b["boundary_points"]


def test_worst_frame_pictures_are_written(quick_report):
    out, _, doc = quick_report
    assert doc["worst_pictures"]
    for p in doc["worst_pictures"]:
        assert (out / p).stat().st_size > 0


def test_eval_of_a_dataset_with_truth_matches_direct_scoring(tmp_path):
    from floorscan.evaluation.scoring import score_columns, summarise_columns
    from floorscan.pipeline.config import Config
    from floorscan.pipeline.mapper import ranger_from_config
    from floorscan.sim import World, simulate_run

    run = simulate_run(World.builtin("room"), seconds=1.0, seed=4, threads=2)
    ds = run.write_dataset(tmp_path / "ds")
    out = tmp_path / "out"
    table_path = tmp_path / "table.json"
    table = run.camera.ground_table(spacing_px=8)
    table.save(table_path)
    rc = main(
        ["eval", str(ds), "--truth", str(ds / "truth"), "--table", str(table_path), "-o", str(out)]
    )
    assert rc == 0
    doc = json.loads((out / "report.json").read_text())
    m = doc["scenarios"][0]["metrics"]
    ranger = ranger_from_config(table, Config())  # the default range sensor, built directly
    expected = summarise_columns(
        [
            score_columns(ranger.scan(run.images[k]), run.truth.status[k], run.truth.points[k])
            for k in range(len(run))
        ]
    )
    assert m["frames"] == len(run)
    assert m["boundary"]["error_rate"] == pytest.approx(expected.error_rate)
    assert m["boundary"]["columns"] == expected.columns
    assert set(m["map"]) == {"odometry", "true_poses"}


def test_lighting_is_written_into_the_world_file():
    text = with_lighting(
        "name = 'x'\n[lighting]\nambient = 0.5\n[[walls]]\nfrom = [0, 0]\n", 0.4, 0.1
    )
    assert "[lighting]\nambient = 0.5\nexposure = 0.4\nexposure_jitter = 0.1\n[[walls]]" in text
    text = with_lighting("[lighting]\nexposure = 1.0\nexposure_jitter = 0.03\n", 1.5, 0.08)
    assert text.count("exposure =") == 1 and "exposure = 1.5" in text
    assert "exposure_jitter = 0.08" in text
    world = Scenario("corridor", lighting="dim").build_world()
    assert world.name == "corridor"
    shadow = "{ strength = 0.5, length_m = 0.04 }"
    text = with_lighting("[lighting]\ncontact_shadow = 1\n", 1.0, 0.03, {"contact_shadow": shadow})
    assert text.count("contact_shadow") == 1 and f"contact_shadow = {shadow}" in text
    shadowed = Scenario("room", lighting="shadowed")
    assert shadowed.name == "room-shadowed-s0" and shadowed.build_world().name == "room"


def test_frames_to_reliable_names_its_local_map():
    from floorscan.evaluation.map_metrics import frames_to_reliable

    with pytest.raises(ValueError, match="local_map"):
        frames_to_reliable(
            [], None, {}, local_size_m=4.0, max_range_m=3.0, starts=[0], local_map="x"
        )


def test_covered_range_stops_at_the_first_row_without_ground():
    """A table whose ground is x = 1 + 0.01 (h - 1 - v) m straight ahead, with no ground from
    node row 2 up in the left half and none at all in one column: the covered range is the
    range at the highest row of the ground run from the bottom (bilinear between nodes, so
    the last full node row below the gap), 0 where the bottom has none."""
    import numpy as np
    from floorscan.evaluation.map_metrics import covered_range_m
    from floorscan.ranging.ground_table import GroundTable

    w, h, sp = 65, 49, 8
    nu, nv = GroundTable.node_shape_for(image_width=w, image_height=h, spacing_px=sp)
    v = np.arange(nv)[:, None] * sp + 0 * np.arange(nu)[None, :]
    x = 1.0 + 0.01 * (h - 1 - v)
    y = np.zeros_like(x)
    x[:3, : nu // 2] = np.nan  # node rows 0-2 (v <= 16) of the left half: no ground
    x[:, -1] = np.nan  # the rightmost node column: no ground at all
    t = GroundTable.from_arrays(x, y, image_width=w, image_height=h, spacing_px=sp)
    cols = np.array([0.0, 8.0, 40.0, 56.0, 64.0])
    got = covered_range_m(t, cols, row_step_px=1.0)
    # left half: ground from v = 24 (node row 3) down; v in (16, 24) interpolates with NaN
    assert got[0] == pytest.approx(1.0 + 0.01 * (h - 1 - 24))
    assert got[1] == pytest.approx(1.0 + 0.01 * (h - 1 - 24))
    # right half: ground to the top row
    assert got[2] == pytest.approx(1.0 + 0.01 * (h - 1))
    # next to and on the column without ground
    assert got[4] == 0.0
    assert 0.0 <= got[3] <= 1.0 + 0.01 * (h - 1)


def test_the_suite_drives_the_textured_floors_faster_too():
    fast = [s for s in full_suite(seconds=1.0) if s.speed_mps == FAST_SPEED_MPS]
    assert sorted(s.world for s in fast) == sorted(TEXTURED_WORLDS)
    assert all(s.odometry == "default" and s.name.endswith("-0.5mps-s0") for s in fast)
    assert Scenario("tiles", speed_mps=0.5).build_robot().speed_mps == 0.5
    with pytest.raises(OptionError, match="speed_mps"):
        Scenario("tiles", speed_mps=0.0)
