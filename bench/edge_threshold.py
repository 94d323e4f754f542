"""The edge ranger's threshold and refinement on every scenario of the simulated suite (issue 13
item 3), with the ground table chosen so that calibration coverage does not mask the ranger:
boundary error rate (share of columns wrong, `floorscan.evaluation.scoring`) per scenario,
per world group and pooled, for each option set.

    .venv/bin/python bench/edge_threshold.py [--table exact|all|trusted] [--only corridor]
        [--cache DIR] [--seconds 30]

`--table exact`: the camera's exact table; `all`: calibrated from the simulated checkerboard
with `coverage = "all"`; `trusted`: calibrated with the default coverage (what `floorscan eval`
uses). `--cache DIR` keeps each simulated scenario (frames, truth, the three tables) as
DIR/NAME.npz, so a second run only ranges. Prints a markdown table.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Dict, List

import numpy as np
from floorscan import VisualRanger
from floorscan.evaluation.calibration_error import calibrated_table
from floorscan.evaluation.scenarios import full_suite
from floorscan.evaluation.scoring import score_columns
from floorscan.pipeline.config import Config
from floorscan.ranging.ground_table import GroundTable
from floorscan.sim import simulate_run

VARIANTS: Dict[str, Dict[str, object]] = {
    "fixed T=10, sub_pixel": dict(
        threshold=10.0, noise_multiple=0.0, contrast=0.0, refinement="sub_pixel"
    ),
    "fixed T=10, step": dict(threshold=10.0, noise_multiple=0.0, contrast=0.0),
    "noise only (k=4), step": dict(contrast=0.0),
    "contrast only (0.12), step": dict(noise_multiple=0.0),
    "noise + contrast, sub_pixel": dict(refinement="sub_pixel"),
    "defaults (noise + contrast, step)": dict(),
}
TABLE_KEYS = {"exact": "t_exact", "all": "t_all", "trusted": "t_def"}


def load_case(scenario, cache: Path | None) -> Dict[str, object]:
    """Frames, truth and the three tables of one scenario, simulated or from the cache."""
    path = cache / f"{scenario.name}.npz" if cache else None
    if path is not None and path.exists():
        z = np.load(path)
        return {k: z[k] for k in z.files}
    camera = scenario.build_camera()
    run = simulate_run(
        scenario.build_world(),
        camera=camera,
        robot=scenario.build_robot(),
        seconds=scenario.seconds,
        seed=scenario.seed,
        threads=1,
    )
    kw = Config().calibration.kwargs()
    case = {
        "images": np.asarray(run.images),
        "status": np.asarray(run.truth.status),
        "points": np.asarray(run.truth.points),
        "t_def": calibrated_table(camera, calibration=kw)[0].to_json(),
        "t_all": calibrated_table(camera, calibration={**kw, "coverage": "all"})[0].to_json(),
        "t_exact": camera.ground_table(spacing_px=Config().calibration.spacing_px).to_json(),
    }
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(path, **case)
    return case


def wrong_columns(
    case: Dict[str, object], table_key: str, options: Dict[str, object]
) -> np.ndarray:
    table = GroundTable.from_json(str(case[table_key]))
    ranger = VisualRanger(table, **options)
    images, status, points = case["images"], case["status"], case["points"]
    return np.concatenate(
        [
            score_columns(ranger.scan(images[f], timestamp=float(f)), status[f], points[f]).wrong
            for f in range(len(images))
        ]
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--table", choices=sorted(TABLE_KEYS), default="exact")
    ap.add_argument("--only", default="")
    ap.add_argument("--cache", type=Path, default=None)
    ap.add_argument("--seconds", type=float, default=30.0)
    args = ap.parse_args()
    key = TABLE_KEYS[args.table]
    rows: Dict[str, List[np.ndarray]] = {}
    names = []
    groups: Dict[str, str] = {}
    for sc in full_suite(seconds=args.seconds):
        if args.only not in sc.name or sc.odometry != "default":
            continue  # odometry variants range the same frames as their seed
        case = load_case(sc, args.cache)
        rows[sc.name] = [wrong_columns(case, key, o) for o in VARIANTS.values()]
        names.append(sc.name)
        groups[sc.name] = sc.group
    head = "| scenario | " + " | ".join(VARIANTS) + " |"
    print(head)
    print("|---|" + "---:|" * len(VARIANTS))

    def line(label: str, parts: List[List[np.ndarray]]) -> str:
        cells = [100 * np.concatenate([p[i] for p in parts]).mean() for i in range(len(VARIANTS))]
        return f"| {label} | " + " | ".join(f"{c:.1f} %" for c in cells) + " |"

    for n in names:
        print(line(n, [rows[n]]))
    print(line("**all scenarios (columns pooled)**", [rows[n] for n in names]))
    for g in dict.fromkeys(groups.values()):
        print(line(f"group {g}", [rows[n] for n in names if groups[n] == g]))


if __name__ == "__main__":
    main()
