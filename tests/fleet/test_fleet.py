"""`floorscan fleet` on a local Ray instance with two workers (and in-process): per-recording
outputs equal `floorscan run`'s, the merged map equals the runs summed by hand, failing
recordings are reported while the others finish, a killed worker is retried, Ctrl-C keeps what
finished, and recordings are grouped by map frame."""

from __future__ import annotations

import json
import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from fleet_recordings import make_recording, sum_by_hand
from floorscan.cli import main
from floorscan.errors import ConfigError, OptionError
from floorscan.fleet.jobs import map_fleet, map_recording
from floorscan.fleet.spec import Recording, parse_recording, read_fleet_toml, with_defaults
from floorscan.mapping.evidence import EvidenceMap
from synthetic_dataset import camera_table

STARTS = {"a": (0.0, 0.0, 0.0), "b": (0.0, 0.0, 0.0), "c": (0.8, 0.4, 1.2)}


@pytest.fixture(scope="module")
def ray_local():
    ray = pytest.importorskip("ray", reason="ray is not installed (pip install 'floorscan[fleet]')")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
    yield ray
    ray.shutdown()


@pytest.fixture(scope="module")
def recs(tmp_path_factory):
    """Three recordings of the room: a and b start at the same pose, c elsewhere."""
    d = tmp_path_factory.mktemp("fleet")
    camera_table().save(d / "table.json")
    for k, (name, start) in enumerate(STARTS.items()):
        make_recording(d / name, n=20, seed=k, start=start)
    return d


def recordings(d: Path, names=("a", "b", "c")):
    return [Recording(input=str(d / n), table=str(d / "table.json")) for n in names]


@pytest.fixture(scope="module")
def serial_runs(recs, tmp_path_factory):
    """Each recording through plain `floorscan run`, one after the other."""
    out = tmp_path_factory.mktemp("serial")
    for n in STARTS:
        assert (
            main(["run", str(recs / n), "--table", str(recs / "table.json"), "-o", str(out / n)])
            == 0
        )
    return out


def evidence(path: Path) -> EvidenceMap:
    return EvidenceMap.load(path / "map.evidence.npz")


def test_merged_map_on_ray_equals_the_runs_in_sequence_summed(
    ray_local, recs, serial_runs, tmp_path
):
    result = map_fleet(recordings(recs), tmp_path, ray="local", shared_frame=True, progress=False)
    assert [r["status"] for r in result.recordings] == ["ok"] * 3
    assert result.merged == ["merged"] and result.groups == [["a", "b", "c"]]
    for n in STARTS:  # per-recording outputs as `floorscan run` writes them
        for f in ("map.pgm", "map.yaml", "scans.csv", "map.evidence.npz"):
            assert (tmp_path / n / f).read_bytes() == (serial_runs / n / f).read_bytes(), (n, f)
        assert (tmp_path / n / "summary.json").is_file() and (tmp_path / n / "run.log").is_file()
    origin, total = sum_by_hand([evidence(serial_runs / n) for n in STARTS])
    merged = evidence(tmp_path / "merged")
    assert np.array_equal(merged.values, total)
    assert merged.origin_m == pytest.approx(origin, abs=1e-12)
    # The merged map_server map is the one `floorscan merge` makes from the serial runs.
    assert main(["merge", *(str(serial_runs / n) for n in STARTS), "-o", str(tmp_path / "m")]) == 0
    assert (tmp_path / "merged" / "map.pgm").read_bytes() == (
        tmp_path / "m" / "map.pgm"
    ).read_bytes()
    summary = json.loads((tmp_path / "merged" / "summary.json").read_text())
    assert [i["recordings"] for i in summary["inputs"]] == [["a"], ["b"], ["c"]]
    fleet = json.loads((tmp_path / "fleet.json").read_text())
    assert fleet["mode"] == "ray local" and len(fleet["recordings"]) == 3


def test_in_process_gives_the_same_result_and_groups_by_start_pose(recs, serial_runs, tmp_path):
    result = map_fleet(recordings(recs), tmp_path, progress=False)
    # a and b start at the same pose: one frame, merged; c starts elsewhere: kept apart.
    assert result.mode == "serial" and result.groups == [["a", "b"], ["c"]]
    assert result.merged == ["merged"] and not (tmp_path / "merged-2").exists()
    origin, total = sum_by_hand([evidence(serial_runs / n) for n in ("a", "b")])
    assert np.array_equal(evidence(tmp_path / "merged").values, total)


def test_fleet_command_names_the_merged_map_and_keeps_an_existing_folder(recs, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["fleet", str(recs / "a"), str(recs / "b"), "--table", str(recs / "table.json")]
    assert main(argv + ["-o", str(out)]) == 0
    printed = capsys.readouterr().out
    # a and b share their start pose: one merged map, named by its file
    assert f"merged map: {out / 'merged' / 'map.yaml'}" in printed
    assert "merged: merged" not in printed and (out / "merged" / "map.yaml").is_file()
    assert main(argv + ["-o", str(out)]) == 1  # nothing overwritten without --force
    assert "pass --force" in capsys.readouterr().err
    assert main(argv + ["-o", str(out), "--force"]) == 0


def test_failing_recordings_are_reported_and_the_others_written(ray_local, recs, tmp_path, capsys):
    (tmp_path / "bad.json").write_text("{ not json")
    argv = [
        "fleet",
        str(recs / "a"),
        str(recs / "missing"),
        f"{recs / 'b'}::{tmp_path / 'bad.json'}",
    ]
    rc = main(
        argv + ["--table", str(recs / "table.json"), "-o", str(tmp_path / "out"), "--ray", "local"]
    )
    assert rc == 1
    fleet = json.loads((tmp_path / "out" / "fleet.json").read_text())
    by_name = {r["name"]: r for r in fleet["recordings"]}
    assert by_name["a"]["status"] == "ok"
    assert by_name["missing"]["status"] == "failed" and "not found" in by_name["missing"]["error"]
    assert by_name["b"]["status"] == "failed" and "ground table" in by_name["b"]["error"]
    assert (tmp_path / "out" / "a" / "map.yaml").is_file()
    assert (tmp_path / "out" / "merged" / "map.yaml").is_file()
    assert "missing: failed" in capsys.readouterr().out


def crash_first_attempt():
    """A job that kills its own worker process the first time it maps recording `b` (marker
    file). Made inside a function so that Ray ships it by value (tests/ is not importable)."""

    def job(recording, out_dir):
        marker = Path(out_dir).parent / f".attempted-{recording.name}"
        if recording.name == "b" and not marker.exists():
            marker.touch()
            os.kill(os.getpid(), signal.SIGKILL)
        return map_recording(recording, out_dir)

    return job


def test_a_worker_killed_mid_task_is_retried_by_ray(ray_local, recs, tmp_path):
    result = map_fleet(
        recordings(recs),
        tmp_path / "retry",
        ray="local",
        max_retries=2,
        map_one=crash_first_attempt(),
        progress=False,
    )
    assert (tmp_path / "retry" / ".attempted-b").exists(), result.recordings  # it did die once
    assert [r["status"] for r in result.recordings] == ["ok"] * 3
    # Without retries the crash is reported and the others finish.
    result = map_fleet(
        recordings(recs),
        tmp_path / "once",
        ray="local",
        max_retries=0,
        map_one=crash_first_attempt(),
        progress=False,
    )
    status = {r["name"]: r for r in result.recordings}
    assert status["b"]["status"] == "failed" and "WorkerCrashed" in status["b"]["error"]
    assert status["a"]["status"] == status["c"]["status"] == "ok"


def test_ctrl_c_cancels_the_rest_and_keeps_what_finished(ray_local, recs, tmp_path):
    out = tmp_path / "int"

    def slow_c(recording, out_dir):
        if recording.name == "c":
            time.sleep(120)
        return map_recording(recording, out_dir)

    main_thread = threading.get_ident()

    def interrupt_when_a_and_b_are_done():
        while not all((out / n / "summary.json").is_file() for n in ("a", "b")):
            time.sleep(0.05)
        time.sleep(0.5)
        signal.pthread_kill(main_thread, signal.SIGINT)

    # Python's own Ctrl-C (KeyboardInterrupt), whatever handler an earlier test left behind
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Thread(target=interrupt_when_a_and_b_are_done, daemon=True).start()
        result = map_fleet(recordings(recs), out, ray="local", map_one=slow_c, progress=False)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert result.interrupted
    status = {r["name"]: r["status"] for r in result.recordings}
    assert status == {"a": "ok", "b": "ok", "c": "cancelled"}
    assert (out / "merged" / "map.yaml").is_file() and not (out / "c" / "map.yaml").exists()


def test_serial_ctrl_c_keeps_the_finished_recordings(recs, tmp_path):
    def interrupted_on_b(recording, out_dir):
        if recording.name == "b":
            raise KeyboardInterrupt
        return map_recording(recording, out_dir)

    result = map_fleet(
        recordings(recs), tmp_path, map_one=interrupted_on_b, shared_frame=True, progress=False
    )
    assert result.interrupted
    assert [r["status"] for r in result.recordings] == ["ok", "interrupted", "cancelled"]
    assert np.array_equal(evidence(tmp_path / "merged").values, evidence(tmp_path / "a").values)


def test_fleet_file_gives_each_robot_its_table_and_config(recs, tmp_path):
    (tmp_path / "coarse.toml").write_text("[map]\ncell_size_m = 0.05\n")
    rel = os.path.relpath(recs, tmp_path)
    (tmp_path / "fleet.toml").write_text(
        f'[defaults]\ntable = "{rel}/table.json"\n\n'
        f'[[recording]]\ninput = "{rel}/a"\nname = "robot-1"\n\n'
        f'[[recording]]\ninput = "{rel}/b"\nconfig = "coarse.toml"\n'
    )
    specs = read_fleet_toml(tmp_path / "fleet.toml")
    assert specs[0].table == str(tmp_path / rel / "table.json") and specs[1].config.endswith(
        "coarse.toml"
    )
    rc = main(["fleet", "--fleet", str(tmp_path / "fleet.toml"), "-o", str(tmp_path / "out")])
    assert rc == 1  # both mapped, but 4 cm and 5 cm maps do not merge
    fleet = json.loads((tmp_path / "out" / "fleet.json").read_text())
    assert [r["status"] for r in fleet["recordings"]] == ["ok", "ok"]
    assert "cell" in fleet["merge_error"] and not (tmp_path / "out" / "merged").exists()
    assert evidence(tmp_path / "out" / "b").cell_size_m == 0.05
    assert evidence(tmp_path / "out" / "robot-1").cell_size_m == 0.04


def test_recording_specs_are_checked(tmp_path):
    assert parse_recording("x/y.bag::t.json") == Recording(input="x/y.bag", table="t.json")
    with pytest.raises(OptionError, match="REC::TABLE"):
        parse_recording("x::")
    named = with_defaults(
        [Recording("d/run1"), Recording("e/run1/"), Recording("v.mp4")], table="t"
    )
    assert [r.name for r in named] == ["run1", "run1-2", "v"] and named[0].table == "t"
    with pytest.raises(OptionError, match="merged"):
        with_defaults([Recording("merged")])
    (tmp_path / "f.toml").write_text('[[recording]]\ninput = "a"\ncolour = "red"\n')
    with pytest.raises(ConfigError, match="colour"):
        read_fleet_toml(tmp_path / "f.toml")
    (tmp_path / "g.toml").write_text("[defaults]\n")
    with pytest.raises(ConfigError, match="no \\[\\[recording\\]\\]"):
        read_fleet_toml(tmp_path / "g.toml")
    with pytest.raises(OptionError, match="max_retries"):
        map_fleet([Recording("a")], tmp_path / "o", max_retries=-1)
