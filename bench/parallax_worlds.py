"""The floor-parallax cue through the pipeline (`[parallax] enabled = true`) against the edge
ranger alone, on simulated runs with the default odometry noise: built-in worlds, held-out
world files, and held-out floors swapped into them (`--floor tiles|wood`, the floors of
bench/motion_cue_probe.py).

    .venv/bin/python bench/parallax_worlds.py --worlds tiles parquet room corridor --seeds 3 4
    .venv/bin/python bench/parallax_worlds.py --worlds bench/worlds/office_l.toml --floor tiles

Prints per world and seed: columns wrong (status, or > 10 cm), within 2 m and within 1 m of
the camera, for the edge ranger, with the cue at its defaults, and with its memory of the
floor's edges (`memory_min_frames = 2`), and the ranging time per frame. `--floor-lines W`
adds the edge ranger passing lines on the floor up to W [m] wide (`[ranger]
floor_line_width_m`), alone and with the cue and its memory. `--odometry` sets the robot's
odometry error: a named model of `floorscan eval` (perfect, default, drifting) or `xK`, the
default's four errors times K (what the cue tolerates):

    .venv/bin/python bench/parallax_worlds.py --worlds bench/worlds/office_l.toml --floor tiles \
        --floor-lines 0.02 --odometry x4
"""

from __future__ import annotations

import argparse

import numpy as np
from floorscan.errors import FloorscanError
from floorscan.evaluation.calibration_error import calibrated_table
from floorscan.evaluation.case import case_from_run
from floorscan.evaluation.runner import evaluate_case
from floorscan.evaluation.scenarios import ODOMETRY
from floorscan.pipeline.config import Config
from floorscan.sim import Camera, OdometryNoise, Robot, simulate_run
from motion_cue_probe import HELD_OUT_FLOORS, load_world
from slam_local import parse_value


def wrong_within(result, limit_m: float) -> float:
    wrong = total = 0
    for s in result.column_scores:
        sel = np.isfinite(s.true_range_m) & (s.true_range_m <= limit_m)
        wrong += int(s.wrong[sel].sum())
        total += int(sel.sum())
    return wrong / total if total else float("nan")


def odometry_noise(spec: str) -> OdometryNoise:
    """A named odometry model of ``floorscan eval``, or ``xK``: the default's errors times K."""
    if spec.startswith("x"):
        try:
            k = float(spec[1:])
        except ValueError:
            raise argparse.ArgumentTypeError(f"xK needs a number K, got {spec!r}") from None
        errors = [k * e for e in ODOMETRY["default"]]
    elif spec in ODOMETRY:
        errors = ODOMETRY[spec]
    else:
        raise argparse.ArgumentTypeError(f"one of {', '.join(ODOMETRY)} or xK, got {spec!r}")
    wheel, scale, radius, base = errors
    return OdometryNoise(
        wheel_sigma_per_sqrt_m=wheel,
        radius_scale_error=scale,
        radius_difference=radius,
        wheelbase_error=base,
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", nargs="+", default=["tiles", "parquet", "room", "corridor"])
    ap.add_argument("--floor", choices=["as-is", *HELD_OUT_FLOORS], default="as-is")
    ap.add_argument("--seeds", nargs="+", type=int, default=[3])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--floor-lines", type=float, default=0.0, metavar="W")
    ap.add_argument("--odometry", default="default", metavar="MODEL|xK")
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a configuration override for every variant (e.g. parallax.min_baseline_m=0.05)",
    )
    a = ap.parse_args()
    try:
        robot = Robot(odometry=odometry_noise(a.odometry))
    except argparse.ArgumentTypeError as e:
        ap.error(str(e))
    try:
        sets = (o.split("=", 1) for o in a.set)
        base = Config().with_overrides({k: parse_value(v) for k, v in sets})
    except (ValueError, FloorscanError) as e:
        ap.error(str(e))
    cued = base.with_overrides({"parallax.enabled": True})
    memory = cued.with_overrides({"parallax.memory_min_frames": 2})
    configs = [("edge", base), ("parallax", cued), ("+ memory", memory)]
    if a.floor_lines > 0:
        lines = {"ranger.floor_line_width_m": a.floor_lines}
        configs += [
            ("edge + lines", base.with_overrides(lines)),
            ("+ memory + lines", memory.with_overrides(lines)),
        ]
    for spec in a.worlds:
        world = load_world(spec, a.floor)
        for seed in a.seeds:
            camera = Camera()
            run = simulate_run(
                world, camera=camera, robot=robot, seconds=a.seconds, seed=seed, threads=2
            )
            table, _ = calibrated_table(camera, calibration=base.calibration.kwargs())
            row = []
            for name, cfg in configs:
                case = case_from_run(spec, run, table, cell_size_m=cfg.grid.cell_size_m)
                r = evaluate_case(case, cfg)
                b = r.metrics["boundary"]
                row.append(
                    f"{name} {100 * b['error_rate']:.1f} % (2 m {100 * wrong_within(r, 2.0):.1f}, "
                    f"1 m {100 * wrong_within(r, 1.0):.1f}; "
                    f"{r.metrics['ranging_ms_per_frame']:.2f} ms)"
                )
            print(
                f"{spec} ({a.floor}, odometry {a.odometry}) seed {seed}: " + " | ".join(row),
                flush=True,
            )


if __name__ == "__main__":
    main()
