"""``floorscan eval --real``: every real set with truth under a data folder (``../shared/data``
by default), scored for each ranger kind on grey and on colour frames, split by the truth's
status and by row error, in one table; and the rule a default must pass to change: never worse
than the edge ranger on any real set (:func:`default_losses`).

A real set is a floor-mask folder (``images/`` and ``masks/``, the format of
``../shared/data/floors``: :mod:`floorscan.evaluation.floor_masks`) anywhere up to two levels
below the data folder; a set added later is found by its layout, and its description is the
first line of its section in the data folder's ``README.md`` (a ``## <name>/`` heading) when
there is one. Such frames have no camera geometry: readings are scored in image rows, at the
truth's tolerance (max(3 px, 1.25 % of the image height)) and at a strict 3 rows.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..errors import DatasetError
from ..formats.image_io import as_grey
from ..pipeline.config import Config
from ..pipeline.mapper import RANGER_KINDS
from .floor_eval import floor_ranger_factory
from .floor_masks import list_floor_frames, load_floor_frames, range_floor_frames, row_tolerance_px
from .scoring import BOUNDARY, INVALID, NO_BOUNDARY, TOO_CLOSE

MODES = ("grey", "colour")
"""How frames reach the rangers: converted to grey (BT.601 luma, as a mono camera gives them)
or as recorded (RGB)."""

STRICT_ROWS = 3.0
"""The strict row tolerance of the second error column."""

OUTCOMES = ("right", "row_off", "said_boundary", "said_no_boundary", "said_too_close", "invalid")
"""How a column's reading relates to its truth: right; a boundary at the wrong row; or the
wrong status (what the ranger said)."""

_TRUTHS = {"boundary": BOUNDARY, "no_boundary": NO_BOUNDARY, "too_close": TOO_CLOSE}


@dataclasses.dataclass(frozen=True)
class RealSet:
    """A real set with truth: its name (path under the data folder), folder and README line."""

    name: str
    folder: Path
    description: str = ""


def find_real_sets(root) -> List[RealSet]:
    """The floor-mask folders at most two levels below ``root``, sorted by name."""
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f"real data folder {root} does not exist")
    readme = _readme_sections(root / "README.md")
    found = []
    for d in sorted([root, *root.glob("*"), *root.glob("*/*")]):
        if d.is_dir() and (d / "images").is_dir() and (d / "masks").is_dir():
            name = d.relative_to(root).as_posix() if d != root else root.name
            found.append(RealSet(name, d, readme.get(name.split("/")[0], "")))
    if not found:
        raise DatasetError(
            f"no real set with truth under {root}: a set is a folder with images/ and masks/"
        )
    return found


def _readme_sections(path: Path) -> Dict[str, str]:
    """``## name/: text`` headings of the data README -> text."""
    if not path.is_file():
        return {}
    out = {}
    for line in path.read_text(errors="replace").splitlines():
        m = re.match(r"^##\s+([^/\s:]+)/?:?\s*(.*)$", line)
        if m:
            out[m.group(1)] = m.group(2).strip()
    return out


def _empty_counts() -> Dict[str, Dict[str, int]]:
    return {t: {o: 0 for o in OUTCOMES} for t in _TRUTHS}


def classify_columns(
    status: np.ndarray,
    rows: np.ndarray,
    true_status: np.ndarray,
    true_rows: np.ndarray,
    tolerance_px: float,
) -> np.ndarray:
    """Per column, the index in :data:`OUTCOMES` of its reading against its truth."""
    s = np.asarray(status).astype(np.int64)
    t = np.asarray(true_status).astype(np.int64)
    out = np.empty(s.shape, np.int64)
    said = {
        BOUNDARY: OUTCOMES.index("said_boundary"),
        NO_BOUNDARY: OUTCOMES.index("said_no_boundary"),
        TOO_CLOSE: OUTCOMES.index("said_too_close"),
    }
    out[:] = OUTCOMES.index("invalid")
    for code, idx in said.items():
        out[s == code] = idx
    same = s == t
    out[same] = OUTCOMES.index("right")
    both = same & (s == BOUNDARY)
    off = np.abs(np.asarray(rows, float) - np.asarray(true_rows, float)) > tolerance_px
    out[both & off] = OUTCOMES.index("row_off")
    out[s == INVALID] = OUTCOMES.index("invalid")
    return out


def score_real_set(
    real: RealSet, cfg: Config, kind: str, mode: str, *, loaded=None
) -> Dict[str, object]:
    """Scores one ranger kind on one set in one mode. Returns ``{"columns", "frames",
    "wrong", "wrong_strict", "error_rate", "error_rate_strict", "by_truth": {truth: {outcome:
    n}}, "row_error_px": {"median", "p90"}}`` (row errors of columns where reading and truth
    are both boundaries)."""
    if mode not in MODES:
        raise DatasetError(f"mode must be one of {', '.join(MODES)}, got {mode!r}")
    if loaded is None:
        loaded = load_floor_frames(list_floor_frames(real.folder))
    if mode == "grey":
        loaded = [dataclasses.replace(lf, rgb=as_grey(lf.rgb)) for lf in loaded]
    counts = _empty_counts()
    names = {code: name for name, code in _TRUTHS.items()}
    wrong = wrong_strict = n = 0
    row_errors: List[np.ndarray] = []
    for lf, cols, scan in range_floor_frames(loaded, floor_ranger_factory(cfg, kind)):
        h = lf.rgb.shape[0]
        ts, tr = lf.true_status[cols], lf.true_rows[cols]
        outcome = classify_columns(scan.status_codes, scan.rows, ts, tr, row_tolerance_px(h))
        strict = classify_columns(scan.status_codes, scan.rows, ts, tr, STRICT_ROWS)
        for code, name in names.items():
            sel = ts == code
            for i, o in enumerate(OUTCOMES):
                counts[name][o] += int(np.count_nonzero(outcome[sel] == i))
        wrong += int(np.count_nonzero(outcome != 0))
        wrong_strict += int(np.count_nonzero(strict != 0))
        n += cols.size
        both = (scan.status_codes == BOUNDARY) & (ts == BOUNDARY)
        row_errors.append(np.abs(scan.rows[both] - tr[both]))
    errs = np.concatenate(row_errors) if row_errors else np.zeros(0)
    return {
        "frames": len(loaded),
        "columns": n,
        "wrong": wrong,
        "wrong_strict": wrong_strict,
        "error_rate": wrong / n if n else float("nan"),
        "error_rate_strict": wrong_strict / n if n else float("nan"),
        "by_truth": counts,
        "row_error_px": {
            "median": float(np.median(errs)) if errs.size else float("nan"),
            "p90": float(np.percentile(errs, 90)) if errs.size else float("nan"),
        },
    }


PAPER_EDGE = {
    "ranger.kind": "edge",
    "ranger.threshold": 10.0,
    "ranger.noise_multiple": 0.0,
    "ranger.contrast": 0.0,
    "ranger.refinement": "first_crossing",
}
"""The paper's own edge filter: a fixed threshold on |R| (10, floorscan's fixed default before
the threshold followed each frame; the paper leaves the threshold and the filter's size to
experiment, and the size here is the configured one), the first crossing taken as the
boundary. The baseline no default may lose to, whatever its options."""


PAPER = "edge, the paper's options"
"""The table's label of :data:`PAPER_EDGE`'s row."""


def score_real_sets(
    root,
    cfg: Config,
    *,
    kinds: Sequence[str] = RANGER_KINDS,
    modes: Sequence[str] = MODES,
    sets: Optional[Sequence[RealSet]] = None,
    paper: bool = False,
) -> Dict[str, object]:
    """Every real set under ``root`` (or ``sets``), every kind, every mode. Returns
    ``{"default_kind": str, "sets": {name: {"description", "scores": {mode: {kind:
    score}}}}}``; each score as :func:`score_real_set`. The configured kind is ``cfg``'s;
    the other kinds run with ``cfg``'s options; with ``paper``, a row :data:`PAPER` holds the
    paper's own filter (:data:`PAPER_EDGE`)."""
    for k in kinds:
        if k not in RANGER_KINDS:
            raise DatasetError(f"unknown ranger kind {k!r}: expected one of {RANGER_KINDS}")
    out: Dict[str, object] = {"default_kind": cfg.ranger.kind, "sets": {}}
    for real in sets if sets is not None else find_real_sets(root):
        loaded = load_floor_frames(list_floor_frames(real.folder))
        scores = {
            mode: {kind: score_real_set(real, cfg, kind, mode, loaded=loaded) for kind in kinds}
            for mode in modes
        }
        if paper:
            original = cfg.with_overrides(PAPER_EDGE)
            for mode in modes:
                scores[mode][PAPER] = score_real_set(real, original, "edge", mode, loaded=loaded)
        out["sets"][real.name] = {"description": real.description, "scores": scores}
    return out


def default_losses(result: Dict[str, object], *, baseline: str = "edge") -> List[str]:
    """Where the configured kind has more wrong columns than ``baseline`` or the paper's own
    filter (the :data:`PAPER` row, where scored), at the truth's tolerance or at 3 rows: one
    line per set, mode and baseline; empty when it never loses."""
    default = result["default_kind"]
    losses = []
    for name, entry in result["sets"].items():
        for mode, by_kind in entry["scores"].items():
            if default not in by_kind or baseline not in by_kind:
                raise DatasetError(f"the table of {name} ({mode}) lacks {default} or {baseline}")
            for other in (baseline, PAPER):
                if other not in by_kind:
                    continue
                d, b = by_kind[default], by_kind[other]
                for key in ("wrong", "wrong_strict"):
                    if d[key] > b[key]:
                        losses.append(
                            f"{name} ({mode}): {default} {d[key]} wrong columns against "
                            f"{other} {b[key]} ({key})"
                        )
    return losses


def _pct(part: int, whole: int) -> str:
    return f"{100 * part / whole:.1f} %" if whole else "-"


def _split(counts: Dict[str, Dict[str, int]], truth: str, *parts: str) -> str:
    """'wrong (part / part ...) of n' for the columns of one truth status."""
    t = counts[truth]
    total = sum(t.values())
    if not total:
        return "none"
    inner = " / ".join(_pct(t[p], total) for p in parts)
    return f"{_pct(total - t['right'], total)} ({inner}) of {total}"


def format_real_table(result: Dict[str, object], *, command: str = "") -> str:
    """One Markdown table: per set, mode and kind, the share of columns wrong (truth's
    tolerance / 3 rows), then per truth status the share wrong and what was said instead, and
    the row error of boundaries found on both sides."""
    default = result["default_kind"]
    lines = []
    if command:
        lines += [f"Command: `{command}`", ""]
    lines += [
        "| set | frames | kind | wrong (tolerance / 3 rows) | truth boundary: wrong (row off / "
        "said nb / said tc) | truth no_boundary: wrong (said b / said tc) | truth too_close: "
        "wrong (said b / said nb) | row error median / p90 [px] |",
        "|---|---:|---|---:|---|---|---|---:|",
    ]
    for name, entry in result["sets"].items():
        for mode, by_kind in entry["scores"].items():
            for kind, s in by_kind.items():
                c = s["by_truth"]
                label = f"**{kind}** (default)" if kind == default else kind

                r = s["row_error_px"]
                lines.append(
                    f"| {name}, {mode} | {s['frames']} | {label} | "
                    f"{_pct(s['wrong'], s['columns'])} / {_pct(s['wrong_strict'], s['columns'])} | "
                    f"{_split(c, 'boundary', 'row_off', 'said_no_boundary', 'said_too_close')} | "
                    f"{_split(c, 'no_boundary', 'said_boundary', 'said_too_close')} | "
                    f"{_split(c, 'too_close', 'said_boundary', 'said_no_boundary')} | "
                    f"{r['median']:.1f} / {r['p90']:.1f} |"
                )
    losses = default_losses(result) if "edge" in _kinds_of(result) else []
    lines.append("")
    if losses:
        lines.append(f"The default ({default}) loses: " + "; ".join(losses))
    else:
        lines.append(
            f"The default ({default}) is no worse than the edge ranger (nor the paper's own "
            "filter, where scored) on every set."
        )
    return "\n".join(lines) + "\n"


def _kinds_of(result: Dict[str, object]) -> set:
    kinds = set()
    for entry in result["sets"].values():
        for by_kind in entry["scores"].values():
            kinds |= set(by_kind)
    return kinds
