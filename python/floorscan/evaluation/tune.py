"""``floorscan tune``: the filter half-width, threshold and refinement with the lowest boundary
error rate on frames with truth (simulated truth or hand-labelled rows), and a label-free
threshold from the carpet's texture noise.

Choice rule: the lowest error rate; among settings within ``tie_tolerance`` of it, the
half-width and refinement whose band of such thresholds is widest, with the threshold at the
band's centre (the setting farthest from failing either way).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .._atomic import PathLike
from ..errors import FileFormatError, OptionError
from ..ranging.auto_threshold import AUTO_K, auto_threshold, texture_noise  # noqa: F401 (re-exported)
from ..ranging.ground_table import GroundTable
from ..ranging.ranger import Refinement, VisualRanger
from .scoring import BOUNDARY, INVALID, NO_BOUNDARY, score_columns

DEFAULT_HALF_WIDTHS = (1, 2, 3, 4, 6, 8)
DEFAULT_THRESHOLDS = tuple(float(t) for t in range(2, 41))
REFINEMENTS = tuple(r.value for r in Refinement)
"""Every ``refinement`` of the core's ``RangerOptions`` (serde names)."""
FIXED_THRESHOLD = {"noise_multiple": 0.0, "contrast": 0.0}
"""The ranger options that make ``threshold`` the paper's fixed threshold (the per-frame terms
off): what ``tune`` searches and what its configuration keeps."""


@dataclass
class TuneSet:
    """Frames with per-column truth: ``images`` (list of (H, W)), ``status`` (N, W) codes,
    ``points`` (N, W, 2) [m] camera ground frame, ``labelled`` (N, W) bool (columns scored)."""

    images: List[np.ndarray]
    status: np.ndarray
    points: np.ndarray
    labelled: np.ndarray
    table: GroundTable

    @property
    def columns(self) -> np.ndarray:
        """Image columns labelled in any frame."""
        return np.nonzero(self.labelled.any(axis=0))[0]


def read_labels_csv(
    path: PathLike, image_names: Sequence[str], table: GroundTable
) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hand labels, CSV with header ``image,column,row``: ``image`` the frame's image path as
    listed in images.txt (or its 0-based index there), ``column`` an image column [px], ``row``
    the boundary row [px, from the top; fractional allowed], empty or ``none`` when the column
    shows floor up to its range limit (no boundary). Returns (status, points, labelled) over
    (frames, image width); the points come from ``table``."""
    path = Path(path)
    n, w = len(image_names), table.image_width
    index = {name: i for i, name in enumerate(image_names)}
    status = np.full((n, w), INVALID, np.int64)
    points = np.full((n, w, 2), np.nan)
    labelled = np.zeros((n, w), bool)
    try:
        f = path.open(newline="", encoding="utf-8")
    except OSError as e:
        raise FileFormatError(f"cannot read labels {path}: {e}") from None
    with f:
        try:
            _read_labels(path, f, index, table, status, points, labelled)
        except UnicodeDecodeError as e:
            raise FileFormatError(f"{path}: not UTF-8 text ({e.reason})") from None
        except csv.Error as e:
            raise FileFormatError(f"{path}: not a CSV file ({e})") from None
    return status, points, labelled


def _read_labels(path, f, index, table, status, points, labelled) -> None:
    n, w = status.shape
    reader = csv.DictReader(f)
    if reader.fieldnames is None or {"image", "column", "row"} - set(reader.fieldnames):
        raise FileFormatError(f"{path}: header must be image,column,row")
    for lineno, rec in enumerate(reader, start=2):
        if None in (rec["image"], rec["column"]):
            raise FileFormatError(f"{path}:{lineno}: expected image,column,row")
        name = rec["image"].strip()
        k = index.get(name)
        if k is None and name.isascii() and name.isdigit():
            k = int(name)
        if k is None or not 0 <= k < n:
            raise FileFormatError(f"{path}:{lineno}: unknown image {name!r}")
        try:
            u = int(rec["column"])
        except ValueError:
            raise FileFormatError(f"{path}:{lineno}: bad column {rec['column']!r}") from None
        if not 0 <= u < w:
            raise FileFormatError(f"{path}:{lineno}: column {u} outside the image (width {w})")
        text = (rec["row"] or "").strip().lower()
        labelled[k, u] = True
        if text in ("", "none", "nan"):
            status[k, u] = NO_BOUNDARY
            continue
        try:
            row = float(text)
        except ValueError:
            raise FileFormatError(f"{path}:{lineno}: bad row {rec['row']!r}") from None
        p = table.lookup(float(u), row)
        if p is None:
            raise FileFormatError(f"{path}:{lineno}: row {row} of column {u} has no ground")
        status[k, u] = BOUNDARY
        points[k, u] = p


@dataclass
class TuneResult:
    """``errors[refine][half_width]`` = error rate per threshold; the chosen setting."""

    half_widths: List[int]
    thresholds: List[float]
    errors: Dict[str, Dict[int, List[float]]]
    half_width: int
    threshold: float
    refine: str
    error_rate: float
    auto: Dict[str, Any] = field(default_factory=dict)

    def as_dict(self) -> Dict[str, Any]:
        return {
            "chosen": {
                "half_width_px": self.half_width,
                "threshold": self.threshold,
                "refinement": self.refine,
                "error_rate": self.error_rate,
            },
            "half_widths": self.half_widths,
            "thresholds": self.thresholds,
            "errors": {r: {str(d): e for d, e in v.items()} for r, v in self.errors.items()},
            "auto_threshold": self.auto,
        }


def error_rate(tune_set: TuneSet, **options: Any) -> float:
    """Share of labelled columns wrong (status or > 10 cm) with these ranger options (fields of
    ``RangerOptions``; ``columns`` are the labelled ones)."""
    ranger = VisualRanger(tune_set.table, **{**options, "columns": tune_set.columns})
    wrong = total = 0
    for k, image in enumerate(tune_set.images):
        scan = ranger.scan(image)
        s = score_columns(scan, tune_set.status[k], tune_set.points[k])
        keep = tune_set.labelled[k][scan.columns.astype(np.intp)]
        wrong += int(s.wrong[keep].sum())
        total += int(keep.sum())
    return wrong / total if total else float("nan")


def _band(errors: Sequence[float], best: float, tol: float) -> Tuple[int, int]:
    """The widest run of consecutive thresholds with error <= best + tol: (start, end) indices."""
    ok = [e <= best + tol for e in errors]
    best_run, start = (0, -1), None
    for i, flag in enumerate(ok + [False]):
        if flag and start is None:
            start = i
        elif not flag and start is not None:
            if i - start > best_run[1] - best_run[0] + 1 or best_run[1] < 0:
                best_run = (start, i - 1)
            start = None
    return best_run


def tune(
    tune_set: TuneSet,
    *,
    half_widths: Sequence[int] = DEFAULT_HALF_WIDTHS,
    thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
    refinements: Sequence[str] = REFINEMENTS,
    base: Optional[Dict[str, Any]] = None,
    tie_tolerance: float = 0.0,
) -> TuneResult:
    """Grid search; see the module docstring for the choice rule. ``base``: the other ranger
    options (``start``, ``max_range_m``; unset: the Rust defaults; the per-frame threshold
    terms are off unless given, :data:`FIXED_THRESHOLD`)."""
    base = {**FIXED_THRESHOLD, **dict(base or {})}
    if not half_widths or not thresholds or not refinements:
        raise OptionError("tune needs at least one half-width, threshold and refinement")
    thresholds = sorted(float(t) for t in thresholds)
    errors: Dict[str, Dict[int, List[float]]] = {}
    for refine in refinements:
        errors[refine] = {}
        for d in half_widths:
            errors[refine][int(d)] = [
                error_rate(
                    tune_set,
                    **{**base, "half_width_px": int(d), "threshold": t, "refinement": refine},
                )
                for t in thresholds
            ]
    best = min(min(v) for per in errors.values() for v in per.values())
    choice = None
    for refine in refinements:
        for d in half_widths:
            a, b = _band(errors[refine][int(d)], best, tie_tolerance)
            if b < 0:
                continue
            width = thresholds[b] - thresholds[a]
            if choice is None or width > choice[0]:
                choice = (width, refine, int(d), thresholds[(a + b) // 2])
    _, refine, d, t = choice
    i = thresholds.index(t)
    return TuneResult(
        [int(x) for x in half_widths], thresholds, errors, d, t, refine, errors[refine][d][i]
    )
