"""``floorscan tune``: filter half-width, threshold and refinement with the lowest boundary
error rate on a dataset with truth; writes them into a config file, plots the curves, and
measures the label-free automatic threshold against the optimum."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import List

from .._atomic import write_atomic
from ..errors import OptionError
from ..evaluation.calibration_error import table_for_dataset
from ..evaluation.case import read_truth_columns
from ..evaluation.tune import (
    AUTO_K,
    FIXED_THRESHOLD,
    REFINEMENTS,
    TuneSet,
    auto_threshold,
    error_rate,
    read_labels_csv,
    tune,
)
from ..formats.dataset import read_images_txt
from ..formats.image_io import read_grey
from ..pipeline.config import Config
from ..pipeline.config_legacy import LEGACY_KEYS
from ..ranging.ranger import VisualRanger
from ._output import FILE, add_output, also_writes, refuse_existing

REFINE_SPELLING = LEGACY_KEYS["ranger.refine"][1]
"""Reads ``--refine`` in either spelling (``subpixel`` or ``sub_pixel``, ``none`` or
``first_crossing``)."""

MAX_VALUES = 1000
"""Most values one option of the grid search may list (the search is their product)."""


def _numbers(text: str, name: str = "values") -> List[float]:
    """``"1,2,4"`` or ``"2:40:2"`` (start:stop:step, stop included): finite numbers, at most
    MAX_VALUES of them (OptionError naming the option otherwise)."""
    import math

    def bad(why: str) -> OptionError:
        return OptionError(f"invalid option `--{name}`: {why}, got {text!r}")

    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise bad("give start:stop:step")
            a, b, c = (float(x) for x in parts)
            if not all(math.isfinite(v) for v in (a, b, c)):
                raise bad("start, stop and step must be finite")
            if c <= 0 or b < a:
                raise bad("step must be > 0 and stop >= start")
            n = math.floor((b - a) / c + 0.5) + 1
            if n > MAX_VALUES:
                raise bad(f"{n} values, more than {MAX_VALUES}")
            return [a + i * c for i in range(n)]
        values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise bad("not a number") from None
    if not values or len(values) > MAX_VALUES or not all(math.isfinite(v) for v in values):
        raise bad(f"give 1 to {MAX_VALUES} finite numbers")
    return values


def register(sub) -> None:
    p = sub.add_parser(
        "tune",
        help="choose the ranger's half-width and threshold on a dataset with truth",
        description="Grid search over half-width x threshold x refinement for the lowest "
        "boundary error rate against the dataset's truth (truth/columns.csv) or hand labels "
        "(CSV image,column,row; docs/evaluation.md). Writes the chosen values into a config "
        "file, a plot of error rate against threshold per half-width, and the automatic "
        "label-free threshold's error.",
    )
    p.add_argument("dataset", help="dataset folder (images.txt)")
    p.add_argument("--truth", help="truth folder with columns.csv (default: DATASET/truth)")
    p.add_argument("--labels", help="hand-labelled boundary rows, CSV image,column,row")
    p.add_argument("--table", help="ground table JSON (default: calibrate, or truth/camera.json)")
    p.add_argument("--config", help="base configuration TOML (default: the defaults)")
    add_output(
        p, FILE, "config file to write (tune.json is written beside it)", default="tuned.toml"
    )
    p.add_argument("--plot", help="plot PNG (default: beside the output, tune.png)")
    also_writes(p, "plot")
    p.add_argument(
        "--frames", type=int, default=60, help="frames used, evenly spread (default %(default)s)"
    )
    p.add_argument(
        "--half-widths", default="1,2,3,4,6,8", help="half-widths [px] (default %(default)s)"
    )
    p.add_argument(
        "--thresholds",
        default="2:40:1",
        help="thresholds, list or start:stop:step (default %(default)s)",
    )
    p.add_argument(
        "--refine",
        default=",".join(REFINEMENTS),
        help="refinements to try (ranger.refinement) (default %(default)s)",
    )
    p.add_argument(
        "--auto-k",
        type=float,
        default=AUTO_K,
        help="multiple of the texture noise for the automatic threshold (default %(default)s)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    if args.frames < 1:
        raise OptionError(f"invalid option `--frames`: must be >= 1, got {args.frames}")
    _numbers(args.thresholds, "thresholds")  # refuse bad specs before any work
    _numbers(args.half_widths, "half-widths")
    out = Path(args.output)
    plot = Path(args.plot) if args.plot else out.with_name("tune.png")
    refuse_existing([(plot, FILE), (out.with_name("tune.json"), FILE)], force=args.force)
    cfg = Config.load(args.config) if args.config else Config()
    dataset = Path(args.dataset)
    truth = Path(args.truth) if args.truth else dataset / "truth"
    table, _ = table_for_dataset(
        dataset, truth, calibration=cfg.calibration.kwargs(), table_path=args.table
    )
    entries = read_images_txt(dataset)
    names = [
        str(e.path.relative_to(dataset)) if e.path.is_absolute() else str(e.path) for e in entries
    ]
    if args.labels:
        status, points, labelled = read_labels_csv(args.labels, names, table)
    else:
        if not (truth / "columns.csv").is_file():
            raise OptionError(f"no truth: {truth}/columns.csv is missing; give --truth or --labels")
        ts = [e.timestamp for e in entries]
        status, points, _ = read_truth_columns(truth / "columns.csv", ts, table.image_width)
        labelled = np.zeros(status.shape, bool)
        labelled[:, VisualRanger(table, columns=cfg.ranger.columns).columns] = True
    frames = np.nonzero(labelled.any(axis=1))[0]
    if frames.size == 0:
        raise OptionError("no labelled frames")
    if frames.size > args.frames:
        frames = frames[np.linspace(0, frames.size - 1, args.frames).round().astype(int)]
    images = [read_grey(entries[k].path) for k in frames]
    tset = TuneSet(images, status[frames], points[frames], labelled[frames], table)
    half_widths = [int(v) for v in _numbers(args.half_widths, "half-widths")]
    base = {"start": cfg.ranger.start, "max_range_m": cfg.ranger.max_range_m, **FIXED_THRESHOLD}
    result = tune(
        tset,
        half_widths=half_widths,
        thresholds=_numbers(args.thresholds, "thresholds"),
        refinements=[REFINE_SPELLING(r.strip()) for r in args.refine.split(",")],
        base=base,
    )
    k = args.auto_k
    auto_t, noise = auto_threshold(
        images,
        half_width=result.half_width,
        columns=tset.columns,
        k=k,
        bottom_margin=cfg.ranger.start.get("bottom_margin", 0),
    )
    auto_err = error_rate(
        tset,
        **base,
        half_width_px=result.half_width,
        threshold=auto_t,
        refinement=result.refine,
    )
    result.auto = {"k": k, "texture_noise": noise, "threshold": auto_t, "error_rate": auto_err}
    tuned = cfg.with_overrides(
        {
            "ranger.half_width_px": result.half_width,
            "ranger.threshold": result.threshold,
            "ranger.refinement": result.refine,
            # The tuned threshold is a fixed one: the per-frame terms stay off.
            **{f"ranger.{k}": v for k, v in FIXED_THRESHOLD.items()},
        }
    )
    tuned.save(out)
    from ..evaluation.plot import plot_curves  # matplotlib: 0.4 s, only for this plot

    plot_curves(
        plot,
        result.thresholds,
        {f"d = {d}": v for d, v in result.errors[result.refine].items()},
        title=f"boundary error rate vs threshold (refine = {result.refine})",
        x_label="threshold (intensity units)",
        y_label="share of columns wrong",
        marker=(result.threshold, result.error_rate, f"chosen d={result.half_width}"),
        vline=(auto_t, f"auto ({k:g} x noise)"),
    )
    write_atomic(out.with_name("tune.json"), json.dumps(result.as_dict(), indent=2))
    print(
        f"tune: {len(images)} frames, {int(tset.labelled.sum())} labelled columns\n"
        f"  chosen: half_width {result.half_width}, threshold {result.threshold:g}, "
        f"refine {result.refine}: error rate {100 * result.error_rate:.2f} %\n"
        f"  automatic (no labels): texture noise {noise:.2f}, threshold {auto_t:.2f} "
        f"({k:g} x noise): error rate {100 * auto_err:.2f} %\n"
        f"  wrote {out}, {plot}, {out.with_name('tune.json')}"
    )
    return 0
