"""The drive suite: built-in carpet worlds with obstacles on the route x speeds x seeds, the
camera robot beside the ideal-laser robot, summarised as collisions per 100 m, waypoints
reached, time and minimum clearance (EVALUATION.md)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Dict, List, Sequence

from .._atomic import write_atomic
from ..sim import Camera, World
from .loop import DriveOptions, drive, make_table
from .obstacles import with_obstacles

SUITE_WORLDS = ("room", "corridor")
"""The built-in carpet worlds (lab and tiles have other floors: the camera's known limits)."""
SUITE_CASES = {"room": (None, 1), "corridor": (6, 3)}
"""Per world: (waypoints of the tour driven, None = all; obstacles placed). The room is small
(3.84 m, already a table, four chairs, a bookcase and a bin): one obstacle; the corridor: its
first six waypoints (about 20 m: along the corridor, into room A and back, into room B and
back), three obstacles."""
SUITE_SPEEDS = (0.3, 0.5, 0.8)


def run_suite(
    out,
    *,
    worlds: Sequence[str] = SUITE_WORLDS,
    speeds: Sequence[float] = SUITE_SPEEDS,
    seeds: Sequence[int] = (0, 1),
    seconds: float = 150.0,
    table: str = "exact",
    scan_matching: bool = True,
    config=None,
    ranger: str = DriveOptions.ranger,
    progress=print,
    stop=None,
) -> List[Dict]:
    """Runs every (world, speed, seed, sensor) for at most ``seconds`` [s] each (``worlds``:
    built-in names or world files; ``config``: the range sensor's configuration, see
    :func:`~floorscan.drive.drive`; ``ranger``: its kind without one); writes
    ``suite.json`` and ``suite.md`` into ``out`` and returns the rows. ``stop``: as for
    :func:`~floorscan.drive.drive`; when it is requested the run under way ends, no other
    starts, and the rows so far are written (the last one with its ``stopped_by_signal``)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    camera = Camera()
    tbl = make_table(camera, table)
    rows: List[Dict] = []
    for name in worlds:
        n_way, count = SUITE_CASES.get(name, (None, 3))
        world, placed = with_obstacles(World.resolve(name), count=count)
        tour = world.tour if n_way is None else world.tour[:n_way]
        for speed in speeds:
            for seed in seeds:
                for sensor in ("camera", "laser"):
                    if stop is not None and stop.requested:
                        break
                    o = DriveOptions(
                        speed_m_s=speed,
                        seconds=seconds,
                        seed=seed,
                        sensor=sensor,
                        table=table,
                        keep_frames=0,
                        scan_matching=scan_matching,
                        ranger=ranger,
                    )
                    s = drive(
                        world,
                        o,
                        camera=camera,
                        table=tbl,
                        waypoints=tour,
                        config=config,
                        stop=stop,
                    ).summary()
                    s.pop("waypoints")
                    s["obstacles"] = placed
                    rows.append(s)
                    if progress:
                        progress(
                            f"{name} {speed} m/s seed {seed} {sensor}: "
                            f"{s['collisions']} contacts, {s['waypoints_reached']}/"
                            f"{s['waypoints_total']} waypoints, {s['duration_s']} s"
                        )
    write_atomic(out / "suite.json", json.dumps(rows, indent=1) + "\n")
    write_atomic(out / "suite.md", suite_table(rows))
    return rows


def suite_table(rows: List[Dict]) -> str:
    """Markdown: per world x speed x sensor, summed over seeds."""
    groups: Dict[tuple, List[Dict]] = {}
    for r in rows:
        groups.setdefault((r["world"], r["speed_m_s"], r["sensor"]), []).append(r)
    lines = [
        "| world | speed [m/s] | sensor | runs | collisions | per 100 m | waypoints reached "
        "| truly within 0.3 m | time [s] | time / laser | min clearance [m] | pose error max [m] |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for (w, v, sensor), rs in sorted(groups.items()):
        dist = sum(r["distance_m"] for r in rs)
        col = sum(r["collisions"] for r in rs)
        got = sum(r["waypoints_reached"] for r in rs)
        truly = sum(r.get("waypoints_reached_true", 0) for r in rs)
        tot = sum(r["waypoints_total"] for r in rs)
        t = sum(r["duration_s"] for r in rs)
        laser = groups.get((w, v, "laser"), [])
        tl = sum(r["duration_s"] for r in laser)
        ratio = f"{t / tl:.2f}" if tl > 0 else "-"
        clr = min(r["min_clearance_m"] for r in rs)
        per100 = 100.0 * col / dist if dist > 0 else 0.0
        perr = max(r.get("pose_error_m_max", float("nan")) for r in rs)
        lines.append(
            f"| {w} | {v} | {sensor} | {len(rs)} | {col} | {per100:.1f} | {got}/{tot} "
            f"({100.0 * got / max(tot, 1):.0f} %) | {truly}/{tot} | {t:.0f} | {ratio} | {clr:.3f} "
            f"| {perr:.2f} |"
        )
    return "\n".join(lines) + "\n"
