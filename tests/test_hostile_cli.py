"""Issue 12's hostile inputs through the ``floorscan`` command, each in its own process
(tests/hostile_corpus.py): every one ends with its documented exit code and at most one line
on stderr (no traceback, no PanicException, no abort), leaves no temporary file, stays under
1 GB of resident memory and finishes (no hang). ``config --check`` refuses exactly the files
``run`` refuses."""

from __future__ import annotations

import pytest
from hostile_corpus import BAD_CONFIGS, CASES, PEAK_RSS_BUDGET_MB, make_shared, run_case


@pytest.fixture(scope="module")
def shared(tmp_path_factory):
    return make_shared(tmp_path_factory.mktemp("hostile-shared"))


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_hostile_input_ends_cleanly(case, shared, tmp_path):
    for module in case.needs:
        pytest.importorskip(module, reason=f"{module} is not installed")
    r = run_case(case, tmp_path / "case", shared)
    assert not r.hang, f"{case.name}: still running after the time limit"
    assert not r.traceback, r.stderr
    assert r.rc in case.exit_codes, f"exit {r.rc}, expected {case.exit_codes}: {r.stderr}"
    if r.rc != 0:
        lines = r.stderr_lines
        assert len(lines) == 1 and lines[0].startswith("floorscan "), r.stderr
    if case.stderr_has:
        assert case.stderr_has in r.stderr, r.stderr
    assert r.temp_files == [], r.temp_files
    assert r.peak_rss_mb < PEAK_RSS_BUDGET_MB, f"{r.peak_rss_mb:.0f} MB"
    if case.check:
        case.check(tmp_path / "case")


def test_config_check_and_run_refuse_the_same_files():
    """The corpus holds each bad configuration twice, for `run` and for `config --check`."""
    names = {c.name for c in CASES}
    for key in BAD_CONFIGS:
        assert {f"config_run_{key}", f"config_check_{key}"} <= names


def test_the_default_configuration_passes_both(shared, tmp_path):
    from floorscan.cli import main
    from floorscan.pipeline.config import Config

    (tmp_path / "c.toml").write_text(Config().to_toml())
    assert main(["config", "--check", str(tmp_path / "c.toml")]) == 0
    args = ["run", str(shared / "room"), "--table", str(shared / "table.json")]
    assert main([*args, "-o", str(tmp_path / "o"), "--config", str(tmp_path / "c.toml")]) == 0
