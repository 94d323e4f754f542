"""A fleet's recordings mapped as Ray tasks (or in-process, one after the other) and merged
into one map (docs/fleet.md).

Each recording is mapped by exactly ``floorscan run`` (:func:`map_recording` runs its command
line) into ``DIR/<name>/``; recordings in one map frame are then merged from their stored
evidence (:mod:`floorscan.mapping.evidence`) into ``DIR/merged/``. A recording that fails is reported
with its error and the others finish; Ctrl-C cancels what is still running and keeps (and
merges) what finished. ``DIR/fleet.json`` records every recording's outcome.
"""

from __future__ import annotations

import argparse
import io
import json
import math
import sys
import time
from contextlib import redirect_stderr, redirect_stdout
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence

from .._atomic import PathLike, write_atomic
from ..commands import run as run_command
from ..errors import FloorscanError, OptionError
from ..mapping.evidence import EvidenceMap, merge_evidence
from ..mapping.merge import describe, write_merged
from .ray_tasks import map_on_ray
from .spec import Recording, with_defaults

SAME_START_M = 1e-3
SAME_START_RAD = 1e-3
"""Recordings whose first poses agree this closely share a map frame."""


def _run_parser() -> argparse.ArgumentParser:
    """The command line of ``floorscan run`` alone (as the CLI's parser reads it)."""
    parser = argparse.ArgumentParser(prog="floorscan")
    run_command.register(parser.add_subparsers(dest="command"))
    return parser


def map_recording(recording: Recording, out_dir: str) -> Dict[str, Any]:
    """Maps one recording with ``floorscan run`` into ``out_dir`` (its output and a ``run.log``
    of what it printed); returns its outcome. Never raises for a bad recording: the error is
    returned, so the fleet goes on."""
    out = Path(out_dir)
    start = time.perf_counter()
    log = io.StringIO()
    result: Dict[str, Any] = {"name": recording.name, "input": recording.input}
    try:
        with redirect_stdout(log), redirect_stderr(log):
            args = _run_parser().parse_args(recording.run_argv(out))
            rc = run_command.main(args)
        summary = json.loads((out / "summary.json").read_text())
        counts = summary.get("counts", {})
        result.update(
            status="interrupted" if rc == 130 or counts.get("interrupted") else "ok",
            frames_mapped=counts.get("frames_mapped"),
            first_pose=summary.get("first_pose"),
        )
    except KeyboardInterrupt:
        result.update(status="interrupted")
    except Exception as e:  # any failure of one recording is reported; the fleet goes on
        result.update(status="failed", error=f"{type(e).__name__}: {e}".splitlines()[0])
    except SystemExit as e:  # argparse refusing the command line
        result.update(status="failed", error=f"bad command line ({e}): {log.getvalue().strip()}")
    result["wall_s"] = round(time.perf_counter() - start, 3)
    if out.is_dir():
        write_atomic(out / "run.log", log.getvalue())
    return result


@dataclass
class FleetResult:
    """What a fleet job did: one outcome per recording (``status`` ok / failed /
    interrupted / cancelled, ``error``), the map-frame groups and the merged folders."""

    recordings: List[Dict[str, Any]]
    groups: List[List[str]] = field(default_factory=list)
    merged: List[str] = field(default_factory=list)
    interrupted: bool = False
    merge_error: Optional[str] = None
    wall_s: float = 0.0
    mode: str = "serial"

    @property
    def failed(self) -> List[Dict[str, Any]]:
        return [r for r in self.recordings if r["status"] != "ok"]

    def as_dict(self) -> Dict[str, Any]:
        return dict(self.__dict__)


def map_fleet(
    recordings: Sequence[Recording],
    out_dir: PathLike,
    *,
    ray: Optional[str] = None,
    table: Optional[str] = None,
    config: Optional[str] = None,
    shared_frame: bool = False,
    max_retries: int = 3,
    workers: Optional[int] = None,
    progress: bool = True,
    map_one: Callable[[Recording, str], Dict[str, Any]] = map_recording,
) -> FleetResult:
    """Maps every recording into ``out_dir/<name>/`` and merges those in one map frame into
    ``out_dir/merged/`` (further frames: ``merged-2/``...).

    ``ray``: None maps in this process, one after the other; ``"local"`` starts Ray on this
    machine (``workers`` CPUs, default all); an address (``"ray://head:10001"``, ``"auto"``)
    joins a cluster, whose workers must see the same files (shared file system). A Ray
    instance already running in this process is used as it is. ``max_retries``: times Ray
    re-runs a recording whose worker died. ``shared_frame``: every recording is in one map
    frame; otherwise recordings share a frame only when their first poses agree (1 mm,
    1 mrad). ``table`` / ``config``: for recordings that give none. ``map_one``: the
    per-recording job (default :func:`map_recording`; wrap it to add logging)."""
    if max_retries < 0:
        raise OptionError(f"invalid option `max_retries`: must be >= 0, got {max_retries}")
    recs = with_defaults(recordings, table=table, config=config)
    if not recs:
        raise OptionError("no recordings to map")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    bar = FleetProgress(len(recs), enabled=progress)
    start = time.perf_counter()
    if ray is None:
        results, interrupted = _serial(recs, out, map_one, bar)
        mode = "serial"
    else:
        results, interrupted = map_on_ray(recs, out, map_one, bar, ray, workers, max_retries)
        mode = f"ray {ray}"
    bar.close()
    result = FleetResult(recordings=results, interrupted=interrupted, mode=mode)
    result.groups = group_by_frame(results, shared_frame=shared_frame)
    try:
        result.merged = _merge_groups(result.groups, out)
    except FloorscanError as e:
        result.merge_error = str(e)
    result.wall_s = round(time.perf_counter() - start, 3)
    write_atomic(out / "fleet.json", json.dumps(result.as_dict(), indent=2, default=float))
    return result


def _serial(recs, out: Path, map_one, bar) -> tuple:
    results: List[Dict[str, Any]] = []
    for k, r in enumerate(recs):
        try:
            res = map_one(r, str(out / r.name))
        except KeyboardInterrupt:
            res = {"name": r.name, "input": r.input, "status": "interrupted"}
        results.append(res)
        bar.update(results)
        if res["status"] == "interrupted":
            results += [_cancelled(x) for x in recs[k + 1 :]]
            return results, True
    return results, False


def _cancelled(r: Recording) -> Dict[str, Any]:
    return {"name": r.name, "input": r.input, "status": "cancelled", "error": "Ctrl-C"}


def group_by_frame(results: Sequence[Dict[str, Any]], *, shared_frame: bool) -> List[List[str]]:
    """Names of the finished recordings, grouped by map frame, largest group first. Without
    ``shared_frame``, recordings share a frame when their first poses agree."""
    done = [r for r in results if r["status"] == "ok" and r.get("first_pose") is not None]
    if shared_frame:
        return [[r["name"] for r in done]] if done else []
    groups: List[tuple] = []
    for r in done:
        x, y, yaw = r["first_pose"]
        for pose, names in groups:
            dyaw = math.remainder(yaw - pose[2], math.tau)
            if math.hypot(x - pose[0], y - pose[1]) <= SAME_START_M and abs(dyaw) <= SAME_START_RAD:
                names.append(r["name"])
                break
        else:
            groups.append(((x, y, yaw), [r["name"]]))
    return sorted((names for _, names in groups), key=len, reverse=True)


def _merge_groups(groups: List[List[str]], out: Path) -> List[str]:
    written = []
    for k, names in enumerate(groups):
        if k > 0 and len(names) < 2:
            continue  # kept apart: its own map is DIR/<name>/map.yaml
        folder = "merged" if k == 0 else f"merged-{k + 1}"
        maps = [EvidenceMap.load(out / n / "map.evidence.npz") for n in names]
        summary = {
            "inputs": [
                {"path": f"{n}/map.evidence.npz", **describe(m)} for n, m in zip(names, maps)
            ]
        }
        write_merged(merge_evidence(maps), out / folder, summary=summary)
        written.append(folder)
    return written


class FleetProgress:
    """One progress line across recordings on stderr (when it is a terminal)."""

    def __init__(self, total: int, *, enabled: bool = True, stream=None) -> None:
        self.stream = stream or sys.stderr
        self.enabled = enabled and self.stream.isatty()
        self.total = total
        self.start = time.perf_counter()

    def update(self, results: Sequence[Dict[str, Any]]) -> None:
        if not self.enabled:
            return
        bad = sum(r["status"] != "ok" for r in results)
        width = 30
        filled = width * len(results) // max(self.total, 1)
        self.stream.write(
            f"\r  recordings [{'#' * filled}{'.' * (width - filled)}] {len(results)}/{self.total}"
            + (f", {bad} not mapped" if bad else "")
            + f"  {time.perf_counter() - self.start:.0f} s   "
        )
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
