"""``floorscan eval``: the scenario suite (or one dataset with truth), scored against ground
truth; a Markdown table, JSON and pictures of the worst frames."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .._atomic import write_atomic
from ..errors import OptionError
from ..evaluation.calibration_error import table_for_dataset
from ..evaluation.case import case_from_dataset
from ..evaluation.demo import SIMULATION_CONFIG
from ..evaluation.floor_eval import run_floor_eval
from ..evaluation.real_sets import default_losses, format_real_table, score_real_sets
from ..evaluation.report import write_report
from ..evaluation.runner import evaluate_case, run_suite
from ..evaluation.scenarios import full_suite, quick_suite
from ..pipeline.config import Config
from ._output import FOLDER, add_output


def register(sub) -> None:
    p = sub.add_parser(
        "eval",
        help="score ranging and mapping against ground truth: the simulated scenario suite, "
        "or a dataset with truth",
        description="Without DATASET: runs the simulated scenario suite (docs/evaluation.md). "
        "With DATASET --truth DIR: scores that run against DIR/columns.csv and/or DIR/map.yaml.",
    )
    p.add_argument("dataset", nargs="?", help="dataset folder to score (default: the suite)")
    p.add_argument(
        "--truth", help="truth folder (columns.csv and/or map.yaml) (default: DATASET/truth)"
    )
    p.add_argument("--table", help="ground table JSON to range DATASET with (default: calibrate)")
    p.add_argument("--quick", action="store_true", help="a small suite (seconds, not minutes)")
    p.add_argument("--seconds", type=float, help="simulated seconds per scenario")
    p.add_argument("--only", help="run only scenarios whose name contains this text")
    p.add_argument("--config", help="configuration TOML (ranger and map settings)")
    p.add_argument("--threads", type=int, default=2, help="render threads (default %(default)s)")
    p.add_argument(
        "--floors",
        help="a folder of real frames with floor masks (images/, masks/; the format of "
        "../shared/data/floors): scored in image rows per clip and floor type",
    )
    p.add_argument(
        "--real",
        nargs="?",
        const="../shared/data",
        metavar="DIR",
        help="score every real set with truth under DIR (without DIR: %(const)s; floor-mask "
        "folders found by their layout) for each ranger kind on grey and colour frames, in one "
        "table with the paper's own filter beside them; exits 3 when the configured kind loses to "
        "the edge ranger or the paper's filter on any set",
    )
    p.add_argument(
        "--ranger",
        choices=["edge", "appearance", "fused", "all"],
        help="range sensor to evaluate (default: the config's ranger.kind; --floors: all)",
    )
    p.add_argument(
        "--cross-validate",
        action="store_true",
        help="--floors: also tune on all clips but one and score the held-out clip, each in turn",
    )
    p.add_argument(
        "--trim-mask-bottom",
        type=int,
        default=0,
        help="--floors diagnostic: replace the masks' bottom N rows by the row above (default "
        "%(default)s, the exact rule)",
    )
    add_output(p, FOLDER, "output folder", default="eval-out")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    # Simulated calibration scenes place the pattern as near as fits in the image (about
    # 0.2-1.2 m out) while the ranger scans to 3 m: without a config, the suite asks the
    # calibration to extrapolate, as a user with a small pattern would.
    cfg = Config.load(args.config) if args.config else SIMULATION_CONFIG()
    command = (
        "floorscan " + " ".join(sys.argv[1:]) if sys.argv[1:2] == ["eval"] else "floorscan eval"
    )
    out = Path(args.output)
    t0 = time.perf_counter()
    if args.real:
        return _real(args, cfg, out, command, t0)
    if args.floors:
        return _floors(args, cfg, out, command, t0)
    if args.ranger and args.ranger != "all":
        cfg = cfg.with_overrides({"ranger.kind": args.ranger})
    elif args.ranger == "all":
        raise OptionError("--ranger all needs --floors (run the suite once per ranger)")
    if args.dataset:
        records = [_dataset_record(args, cfg)]
    else:
        if args.quick:
            scenarios = quick_suite(seconds=args.seconds)
        else:
            scenarios = full_suite(**({"seconds": args.seconds} if args.seconds else {}))
        if args.only:
            scenarios = [s for s in scenarios if args.only in s.name]
            if not scenarios:
                raise OptionError(f"no scenario name contains {args.only!r}")

        def progress(i, result) -> None:
            b = result.metrics.get("boundary", {})
            print(
                f"[{i + 1}/{len(scenarios)}] {result.name}: boundary error "
                f"{100 * b.get('error_rate', float('nan')):.1f} %",
                file=sys.stderr,
            )

        records = run_suite(scenarios, cfg, threads=args.threads, on_result=progress)
    write_report(out, records, command=command)
    print((out / "report.md").read_text(), end="")
    print(
        f"\n{len(records)} run(s) in {time.perf_counter() - t0:.1f} s; report.md, report.json, worst/ in {out}/"
    )
    return 0


def _dataset_record(args: argparse.Namespace, cfg) -> dict:
    dataset = Path(args.dataset)
    truth = Path(args.truth) if args.truth else dataset / "truth"
    table, cal = table_for_dataset(
        dataset,
        truth,
        calibration=cfg.calibration.kwargs(),
        table_path=args.table,
    )
    case = case_from_dataset(dataset, truth, table)
    case.calibration = cal
    t0 = time.perf_counter()
    result = evaluate_case(case, cfg)
    for w in result.worst:
        w["image"] = case.images[w["frame"]]
        if case.true_rows is not None:
            w["truth_rows"] = case.true_rows[w["frame"]]
    return {
        "scenario": {"name": case.name, "group": "dataset"},
        "metrics": result.metrics,
        "wall_s": {"evaluate": time.perf_counter() - t0},
        "result": result,
    }


def _floors(args: argparse.Namespace, cfg, out: Path, command: str, t0: float) -> int:
    import json

    kinds = ["edge", "appearance", "fused"] if args.ranger in (None, "all") else [args.ranger]
    res = run_floor_eval(
        args.floors,
        cfg,
        kinds=kinds,
        cv=args.cross_validate,
        trim_mask_bottom=args.trim_mask_bottom,
    )
    out.mkdir(parents=True, exist_ok=True)
    md = f"# Real floors: {args.floors}\n\nCommand: `{command}`\n\n" + res["markdown"]
    write_atomic(out / "floors.md", md)
    write_atomic(out / "floors.json", json.dumps(res["results"], indent=1, default=float))
    print(md, end="")
    print(f"\nscored in {time.perf_counter() - t0:.1f} s; floors.md, floors.json in {out}/")
    return 0


def _real(args: argparse.Namespace, cfg, out: Path, command: str, t0: float) -> int:
    import json

    kinds = ("edge", "appearance", "fused") if args.ranger in (None, "all") else (args.ranger,)
    if "edge" not in kinds:
        kinds = ("edge", *kinds)
    if cfg.ranger.kind not in kinds:
        kinds = (*kinds, cfg.ranger.kind)
    res = score_real_sets(args.real, cfg, kinds=kinds, paper=True)
    out.mkdir(parents=True, exist_ok=True)
    md = f"# Real sets: {args.real}\n\n" + format_real_table(res, command=command)
    write_atomic(out / "real.md", md)
    write_atomic(out / "real.json", json.dumps(res, indent=1, default=float))
    print(md, end="")
    print(f"\nscored in {time.perf_counter() - t0:.1f} s; real.md, real.json in {out}/")
    return 3 if default_losses(res) else 0
