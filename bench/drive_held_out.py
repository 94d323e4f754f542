"""The drive on held-out world files, camera robot at one or more values of
`VisualSensorModel.confirm_range_m` (and one of `confirmed_clearing`, `persist_range_m`) beside the ideal-laser
robot, worlds x speeds x seeds, run in parallel processes (EVALUATION.md, "A thin leg clears
over several frames; the confirm range at 0.3 m").

    .venv/bin/python bench/drive_held_out.py --worlds bench/worlds/study.toml ...
        [--seeds 0 1 2] [--speeds 0.3 0.5] [--confirm-range 0.3 0.5] [--jobs 2]
        [--confirmed-clearing 0.25] [--persist-range 0] [--results runs.jsonl]

Each run is `floorscan drive --world W --obstacles --speed S --seed N --no-gif` through the
same Python call. Results are appended to ``--results`` one JSON line a run as they finish
(runs already there are not run again), then summed per world and per speed: contacts,
waypoints, and time against the laser robot (sum of the camera runs' durations over the sum
of the laser runs' on the same worlds, speeds and seeds).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
from collections import defaultdict
from pathlib import Path

from floorscan.drive import DriveOptions, VisualSensorModel, drive
from floorscan.drive.obstacles import with_obstacles
from floorscan.sim import World

KEYS = (
    "collisions",
    "distance_m",
    "duration_s",
    "waypoints_reached",
    "waypoints_total",
    "min_clearance_m",
    "pose_error_m_max",
)


def _key(world: str, speed: float, seed: int, sensor: str, *model) -> tuple:
    return (Path(world).stem, round(speed, 3), seed, sensor, *model)


def _run(task) -> dict:
    world_file, speed, seed, sensor, confirm, clearing, persist = task
    world, _ = with_obstacles(World.resolve(world_file))
    given = {
        "confirm_range_m": confirm,
        "confirmed_clearing": clearing,
        "persist_range_m": persist,
    }
    model = VisualSensorModel(**{k: v for k, v in given.items() if v is not None})
    o = DriveOptions(speed_m_s=speed, seed=seed, sensor=sensor, keep_frames=0, model=model)
    s = drive(world, o).summary()
    row = {k: s[k] for k in KEYS}
    row.update(
        world=Path(world_file).stem,
        speed=speed,
        seed=seed,
        sensor=sensor,
        confirm_range_m=confirm,
        confirmed_clearing=clearing,
        persist_range_m=persist,
        contacts=s["contacts"],
    )
    return row


def summarise(rows) -> str:
    laser = {(r["world"], r["speed"], r["seed"]): r for r in rows if r["sensor"] == "laser"}
    lines = [
        "| world | speed | (confirm_range_m, confirmed_clearing, persist_range_m) | runs | contacts | waypoints | time / laser |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    groups = defaultdict(list)
    for r in rows:
        if r["sensor"] == "camera":
            c = (r["confirm_range_m"], r.get("confirmed_clearing"), r.get("persist_range_m"))
            groups[(r["world"], r["speed"], c)].append(r)
            groups[("all", r["speed"], c)].append(r)

    def order(kv):
        (w, speed, c), _ = kv
        return (w == "all", w, speed, tuple(-1.0 if v is None else v for v in c))

    for (w, speed, c), rs in sorted(groups.items(), key=order):
        pairs = [(r, laser.get((r["world"], r["speed"], r["seed"]))) for r in rs]
        cam_t = sum(r["duration_s"] for r, lz in pairs if lz)
        las_t = sum(lz["duration_s"] for r, lz in pairs if lz)
        ratio = f"{cam_t / las_t:.2f}" if las_t else "-"
        lines.append(
            f"| {w} | {speed} | {c} | {len(rs)} | {sum(r['collisions'] for r in rs)} | "
            f"{sum(r['waypoints_reached'] for r in rs)}/{sum(r['waypoints_total'] for r in rs)}"
            f" | {ratio} |"
        )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", nargs="+", required=True)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4, 5])
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.3, 0.5])
    ap.add_argument(
        "--confirm-range",
        type=float,
        nargs="+",
        default=[None],
        help="VisualSensorModel.confirm_range_m values (default: the model's default)",
    )
    ap.add_argument(
        "--confirmed-clearing",
        type=float,
        default=None,
        help="VisualSensorModel.confirmed_clearing of every camera run (default: the model's)",
    )
    ap.add_argument(
        "--persist-range",
        type=float,
        default=None,
        help="VisualSensorModel.persist_range_m of every camera run (default: the model's)",
    )
    ap.add_argument("--no-laser", action="store_true", help="leave out the laser robot")
    ap.add_argument("--no-camera", action="store_true", help="only the laser robot")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--results", default="drive-held-out.jsonl")
    a = ap.parse_args()
    path = Path(a.results)
    rows = [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []
    done = {
        _key(
            r["world"],
            r["speed"],
            r["seed"],
            r["sensor"],
            r["confirm_range_m"],
            r.get("confirmed_clearing"),
            r.get("persist_range_m"),
        )
        for r in rows
    }
    tasks = []
    for w in a.worlds:
        for speed in a.speeds:
            for seed in a.seeds:
                runs = [
                    ("camera", c, a.confirmed_clearing, a.persist_range) for c in a.confirm_range
                ]
                if a.no_camera:
                    runs = []
                if not a.no_laser:
                    runs.append(("laser", None, None, None))
                for sensor, *model in runs:
                    if _key(w, speed, seed, sensor, *model) not in done:
                        tasks.append((w, speed, seed, sensor, *model))
    with mp.get_context("fork").Pool(a.jobs) as pool, path.open("a") as f:
        for row in pool.imap_unordered(_run, tasks):
            rows.append(row)
            f.write(json.dumps(row) + "\n")
            f.flush()
            print(
                f"{row['world']} {row['speed']} seed {row['seed']} {row['sensor']} "
                f"confirm {row['confirm_range_m']} clearing {row['confirmed_clearing']} "
                f"persist {row['persist_range_m']}: "
                f"{row['collisions']} contacts, "
                f"{row['waypoints_reached']}/{row['waypoints_total']}, {row['duration_s']} s",
                flush=True,
            )
    print(summarise(rows))


if __name__ == "__main__":
    main()
