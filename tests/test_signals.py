"""Signals during ``floorscan run`` (real signals to a real process): SIGINT, SIGTERM and SIGHUP
all stop the run after the current frame and save the map, scans, bag, overlay and summary; a
second signal while saving still leaves every finished file whole; no signal, at any moment,
leaves a temporary file; Ctrl-C while the command starts prints one line, no traceback."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from floorscan import OccupancyGrid, read_scans_csv
from floorscan.formats.rosbag import ROSBAGS_MISSING
from hostile_corpus import FLOORSCAN, temp_files
from synthetic_dataset import camera_table, make_dataset

SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("sig")
    make_dataset(d / "room", n=60)
    camera_table().save(d / "table.json")
    return d


def start_run(dataset: Path, out: Path) -> subprocess.Popen:
    args = ["run", str(dataset / "room"), "--table", str(dataset / "table.json"), "-o", str(out)]
    return subprocess.Popen(
        [FLOORSCAN, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )


def wait_for_frames(out: Path, proc: subprocess.Popen, frames: int, timeout_s: float = 60.0):
    """Waits until the scans' temporary file holds `frames` scans (64 lines each)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and proc.poll() is None:
        for tmp in out.glob(".scans.csv.*"):
            try:
                if tmp.read_text().count("\n") > 1 + 64 * frames:
                    return True
            except OSError:
                pass
        time.sleep(0.005)
    return False


def assert_outputs_whole(out: Path, interrupted: bool) -> None:
    assert temp_files(out) == []
    grid = OccupancyGrid.load(out / "map.yaml")
    assert (grid.occupancy_classes() != 1).sum() > 0
    scans = read_scans_csv(out / "scans.csv")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["counts"]["interrupted"] is interrupted
    assert summary["counts"]["frames_mapped"] == len(scans) >= 1
    for name in ("map.pgm", "map.png", "overlay.gif", "bag/metadata.yaml"):
        assert (out / name).is_file(), name


@pytest.mark.parametrize("sig", SIGNALS, ids=[s.name for s in SIGNALS])
def test_a_signal_stops_after_the_frame_and_saves_everything(dataset, tmp_path, sig):
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the bag among the saved outputs
    out = tmp_path / "out"
    proc = start_run(dataset, out)
    assert wait_for_frames(out, proc, 3), "the run never got going"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    assert "Traceback" not in err
    assert_outputs_whole(out, interrupted=True)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["counts"]["signal"] == sig
    assert summary["counts"]["frames_mapped"] < 60


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_second_signal_while_saving_leaves_every_file_whole(dataset, tmp_path, sig):
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the bag among the saved outputs
    out = tmp_path / "out"
    proc = start_run(dataset, out)
    assert wait_for_frames(out, proc, 3)
    proc.send_signal(sig)
    # The second signal: while the frame finishes or while the outputs are written.
    deadline = time.monotonic() + 30
    while not list(out.glob(".map.*")) and not (out / "map.yaml").exists():
        if time.monotonic() > deadline or proc.poll() is not None:
            break
        time.sleep(0.001)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    assert "Traceback" not in err
    assert_outputs_whole(out, interrupted=True)


def send_burst(proc: subprocess.Popen) -> None:
    """Three SIGTERMs 2 ms apart (fewer if the process ends first)."""
    for _ in range(3):
        if proc.poll() is not None:
            break
        proc.send_signal(signal.SIGTERM)
        time.sleep(0.002)


@pytest.mark.parametrize("delay_s", [0.3, 0.6, 1.0, 1.5])
def test_a_burst_of_signals_at_any_moment_leaves_no_temporary_file(dataset, tmp_path, delay_s):
    """Three signals in a row abandon the outputs not yet written; whatever was written is
    whole and nothing temporary is left."""
    out = tmp_path / "out"
    proc = start_run(dataset, out)
    time.sleep(delay_s)
    send_burst(proc)
    _, err = proc.communicate(timeout=120)
    if python_startup(err):
        return
    assert proc.returncode in (0, 128 + signal.SIGTERM), err
    assert "Traceback" not in err
    if out.exists():
        assert temp_files(out) == []
        if (out / "map.yaml").exists():
            OccupancyGrid.load(out / "map.yaml")
        if (out / "summary.json").exists():
            json.loads((out / "summary.json").read_text())


def python_startup(err: str) -> bool:
    """A signal before Python itself finished starting (site import, or the console script's
    own first import line on a loaded machine): no code of the floorscan package ran yet, so
    its handlers could not be installed (docs/limits.md: the first 20-30 ms)."""
    if "init_import_site" in err and "floorscan" not in err:
        return True
    package_frames = [
        line
        for line in err.splitlines()
        if line.strip().startswith("File ") and "/floorscan/" in line
    ]
    return "KeyboardInterrupt" in err and not package_frames


@pytest.mark.parametrize("delay_s", [0.05, 0.08, 0.1, 0.15, 0.2])
def test_ctrl_c_while_starting_prints_one_line(dataset, tmp_path, delay_s):
    """From floorscan's first line on (about 20-30 ms after exec, once Python has started and
    found the package) Ctrl-C prints one line; before that Python's own default applies."""
    proc = start_run(dataset, tmp_path / "out")
    time.sleep(delay_s)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if python_startup(err):
        return
    assert "Traceback" not in err, err
    # Python's own default (before any floorscan code runs) also ends without a traceback.
    assert proc.returncode in (130, -signal.SIGINT), (proc.returncode, err)
    assert len([line for line in err.splitlines() if line.strip()]) <= 1, err
    if (tmp_path / "out").exists():
        assert temp_files(tmp_path / "out") == []


def test_sigterm_stops_other_commands_with_one_line(tmp_path):
    """`floorscan sim` on SIGTERM: exit 143, one line, no half-written dataset. (The signal is
    handled when the native render of the whole run returns: keep the run short.)"""
    out = tmp_path / "sim"
    args = ["sim", "--seconds", "20", "--width", "160", "--height", "120", "--out", str(out)]
    proc = subprocess.Popen(
        [FLOORSCAN, *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(0.8)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists() or not any(out.iterdir())
    assert temp_files(tmp_path) == []


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_ends_a_drive_and_its_outputs_are_written(tmp_path, sig):
    """`floorscan drive`: a stop signal ends the drive after the current frame; the summary,
    the map, the path and the GIF of the frames so far are written whole."""
    out = tmp_path / "drive"
    # slow, so that the tour is not over before the signal on a fast machine
    args = ["drive", "--world", "room", "--speed", "0.1", "--table", "exact", "-o", str(out)]
    proc = subprocess.Popen(
        [FLOORSCAN, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    first = proc.stderr.readline()  # printed as the drive starts
    assert "floorscan drive" in first, first
    time.sleep(2.0)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    assert "Traceback" not in err
    assert temp_files(out) == []
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stopped_by_signal"] == sig
    assert 0 < summary["duration_s"] < 600 and not summary["tour_done"]
    grid = OccupancyGrid.load(out / "map.yaml")
    assert (grid.occupancy_classes() != 1).sum() > 0
    for name in ("path.png", "drive.gif"):
        assert (out / name).is_file(), name


if __name__ == "__main__":  # pragma: no cover
    sys.exit(pytest.main([__file__, "-q"]))


def test_a_burst_as_the_overlay_starts_leaves_no_temporary_file(dataset, tmp_path):
    """The moment most likely to lose a temporary file: the GIF overlay's writer has just been
    created (its temporary file appears) and signals arrive before the run holds it. Repeated,
    with jitter, because the window is a few microseconds wide."""
    rng = np.random.default_rng(7)
    for i in range(8):
        out = tmp_path / f"out{i}"
        proc = start_run(dataset, out)
        deadline = time.monotonic() + 60
        while proc.poll() is None and not list(out.glob(".overlay.gif.*")):
            if time.monotonic() > deadline:
                break
            time.sleep(0.0002)
        time.sleep(float(rng.uniform(0, 0.003)))
        send_burst(proc)
        _, err = proc.communicate(timeout=120)
        assert "Traceback" not in err
        if out.exists():
            assert temp_files(out) == [], f"attempt {i}"


SLOW_IMPORT = """
import signal, time
signal.raise_signal(signal.SIGTERM)
for _ in range({sleeps}):
    time.sleep(0.01)
FINISHED = True
"""


@pytest.fixture
def slow_import(tmp_path, monkeypatch):
    """Writes a module that raises SIGTERM at its own top level and then sleeps ``sleeps`` x
    10 ms; returns its name. SIGTERM's handler is the default for the test's length: a signal
    held at a block's end goes to the handler of before, which an earlier test may have left."""
    monkeypatch.syspath_prepend(str(tmp_path))
    before = signal.signal(signal.SIGTERM, signal.SIG_DFL)
    names = []

    def make(sleeps: int) -> str:
        name = f"slow_import_for_signal_test_{len(names)}_{sleeps}"
        (tmp_path / f"{name}.py").write_text(SLOW_IMPORT.format(sleeps=sleeps))
        names.append(name)
        return name

    yield make
    signal.signal(signal.SIGTERM, before)
    for name in names:
        sys.modules.pop(name, None)


@pytest.mark.parametrize("sleeps", [0, 10], ids=["block-ends-at-once", "import-takes-100ms"])
def test_a_signal_during_an_import_stops_the_command_once_the_import_has_finished(
    slow_import, sleeps
):
    """A signal inside an import (the commands import OpenCV and matplotlib on first use) is
    raised after it: raised inside a C extension's initialisation it left pybind11's module
    half set up ("ImportError: initialization failed") and crashed the interpreter's shutdown.
    Whether the block goes on (the signal arrives at its next line) or ends at once, it stops."""
    from floorscan._signals import Interrupted, handle_signals

    name = slow_import(sleeps)
    went_on = []
    with pytest.raises(Interrupted) as raised:
        with handle_signals():
            __import__(name)
            went_on.append(True)
            if sleeps:
                time.sleep(5.0)  # the held signal ends this wait
    assert sys.modules[name].FINISHED  # the import was not interrupted
    assert raised.value.signum == signal.SIGTERM
    assert went_on == [True]


def test_a_signal_held_through_an_import_goes_to_the_handler_in_place_when_it_ends(
    slow_import,
):
    """The held signal is delivered again to whatever handles it once the import is over (a
    frame loop that ended meanwhile treats it as a signal while saving), not raised blindly."""
    from floorscan._signals import handle_signals

    name = slow_import(10)
    got = []
    with handle_signals():
        __import__(name)  # SIGTERM raised inside, held: nothing raised here
        previous = signal.signal(signal.SIGTERM, lambda signum, _frame: got.append(signum))
        try:
            deadline = time.monotonic() + 5.0
            while not got and time.monotonic() < deadline:
                time.sleep(0.005)
        finally:
            signal.signal(signal.SIGTERM, previous)
    assert got == [signal.SIGTERM]
    assert sys.modules[name].FINISHED


def test_holding_a_signal_leaves_the_host_s_alarm_as_it_found_it(slow_import):
    """The hold borrows SIGALRM: a host's own alarm (a watchdog around `main(argv)`) gets its
    handler and its timer back, the timer less the time held."""
    from floorscan._signals import Interrupted, handle_signals

    name = slow_import(5)
    fired = []

    def host(signum, _frame):
        fired.append(signum)

    before = signal.signal(signal.SIGALRM, host)
    signal.setitimer(signal.ITIMER_REAL, 30.0)
    try:
        with handle_signals():
            pass
        assert signal.getsignal(signal.SIGALRM) is host
        assert 29.0 < signal.getitimer(signal.ITIMER_REAL)[0] <= 30.0
        with pytest.raises(Interrupted):
            with handle_signals():
                __import__(name)  # SIGTERM held, then delivered
                time.sleep(5.0)
        assert signal.getsignal(signal.SIGALRM) is host
        assert 25.0 < signal.getitimer(signal.ITIMER_REAL)[0] < 30.0
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, before)
    assert fired == []


def test_a_killed_run_says_so_and_the_next_run_cleans_up_after_it(dataset, tmp_path):
    """SIGKILL cannot be caught: the folder must say the run did not finish (summary.json
    "complete": false from the start), and the next run into it removes the temporaries the
    killed one left (only names a run writes, only there), then says "complete": true."""
    out = tmp_path / "out"
    proc = start_run(dataset, out)
    assert wait_for_frames(out, proc, 5), "the run never got going"
    proc.kill()
    proc.communicate(timeout=60)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is False
    left = temp_files(out)
    assert any(name.startswith(".scans.csv.") for name in left), left
    # an earlier killed run's bag folder and atomic write, and files that are not ours
    (out / ".bag.k3j9x0a1").mkdir()
    (out / ".bag.k3j9x0a1" / "x.mcap").write_bytes(b"partial")
    (out / ".map.yaml.ab12cd34.tmp").write_text("partial")
    (out / ".notes.txt").write_text("mine")
    (out / ".scans.csv.backup1").write_text("mine too")  # not a temporary's name
    # a local map snapshot's atomic write, in the run's own local/ folder, beside a user's file
    (out / "local").mkdir(exist_ok=True)
    (out / "local" / ".local_0000105.00.png.7g4407ap.png").write_bytes(b"partial")
    (out / "local" / ".mine.png").write_bytes(b"mine")
    args = ["run", str(dataset / "room"), "--table", str(dataset / "table.json"), "-o", str(out)]
    done = subprocess.run(
        [FLOORSCAN, *args, "--force"], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is True
    assert summary["stale_temporaries_removed"] == len(left) + 3
    assert temp_files(out) == [".notes.txt", ".scans.csv.backup1", "local/.mine.png"]
    OccupancyGrid.load(out / "map.yaml")


def test_runs_killed_at_random_times_leave_a_folder_the_next_run_repairs(dataset, tmp_path):
    """A bounded soak: six runs into one folder, each stopped at a random moment by SIGKILL or
    SIGTERM (seeded: the same moments every time). After each, every final-named output that
    exists loads, and the summary says whether its run completed; a last run then leaves every
    output whole and no temporary behind."""
    rng = np.random.default_rng(11)
    out = tmp_path / "out"
    args = ["run", str(dataset / "room"), "--table", str(dataset / "table.json"), "-o", str(out)]
    for k in range(6):
        proc = subprocess.Popen(
            [FLOORSCAN, *args, "--force"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
        )
        time.sleep(float(rng.uniform(0.3, 2.5)))
        sig = signal.SIGKILL if k % 2 == 0 else signal.SIGTERM
        proc.send_signal(sig)
        proc.communicate(timeout=120)
        if (out / "summary.json").exists():
            summary = json.loads((out / "summary.json").read_text())
            assert summary["complete"] in (True, False)
        if (out / "map.yaml").exists() and (out / "map.pgm").exists():
            OccupancyGrid.load(out / "map.yaml")
        if (out / "scans.csv").exists():
            read_scans_csv(out / "scans.csv")
    done = subprocess.run([FLOORSCAN, *args, "--force"], capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert_outputs_whole(out, interrupted=False)
    assert json.loads((out / "summary.json").read_text())["complete"] is True
