"""The evaluation report: a Markdown table per scenario, summaries per world group (carpet
first; groups that break an assumption of the paper listed separately), the goals, JSON, and
pictures of the worst frames (detected and true boundaries drawn)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

from .._atomic import write_atomic
from ..formats.image_io import write_png
from ..ranging.overlay import draw_scan_overlay
from .runner import median_frames
from .scenarios import CARPET
from .scoring import summarise_columns

COLUMNS = [
    ("scenario", "scenario"),
    ("frames", "frames"),
    ("boundary error %", "error_pct"),
    ("median / p90 cm", "point_error"),
    ("calib. max / RMS cm (floor covered to 3 m)", "calibration"),
    ("map agr. odom / true %", "agreement"),
    ("occ. prec / rec %", "occupied"),
    ("free known %", "free_known"),
    ("frames to reliable: local map", "reliable"),
    ("avoidance map, all / ranger-right views", "reliable_avoidance"),
    ("ranging / mapping ms", "speed"),
]


def _pct(x: Optional[float]) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{100 * x:.1f}"


def _num(x: Optional[float], fmt: str = "{:.1f}") -> str:
    return "-" if x is None or not math.isfinite(x) else fmt.format(x)


def calibration_cell(cal: Dict[str, Any]) -> str:
    if cal.get("status") == "measured":
        text = f"{cal['max_cm']:.2f} / {cal['rms_cm']:.2f}"
        if "covered_share" in cal:
            text += f" ({100 * cal['covered_share']:.0f} %)"
        return text
    return str(cal.get("status", "-"))


def _frames(med: Optional[float], rel: Dict[str, Any]) -> str:
    if med is None:
        return "-"
    return f"{med:g}" if math.isfinite(med) else f"> {rel['max_frames_tried']}"


def _reliable_cell(rel: Dict[str, Any]) -> str:
    if not rel:
        return "-"
    text = _frames(rel.get("median_frames"), rel)
    never = rel.get("views_never_reliable", 0)
    if never:
        text += f" ({never} of {len(rel['frames_per_view'])} views > {rel['max_frames_tried']})"
    return text


def row_cells(name: str, m: Dict[str, Any]) -> Dict[str, str]:
    b = m.get("boundary", {})
    maps = m.get("map", {})
    true_map = maps.get("true_poses", {})
    reliable = _reliable_cell(m.get("reliable_local_map", {}))
    avoid = m.get("reliable_avoidance_map", {})
    reliable_avoidance = "-"
    if avoid:
        right = avoid.get("ranger_right_views", 0)
        reliable_avoidance = (
            f"{_frames(avoid.get('median_frames'), avoid)} / "
            f"{_frames(avoid.get('median_frames_ranger_right'), avoid) if right else '-'}"
            f" ({right} of {len(avoid['frames_per_view'])} views)"
        )
    return {
        "scenario": name,
        "frames": str(m.get("frames", "-")),
        "error_pct": _pct(b.get("error_rate")),
        "point_error": f"{_num(b.get('median_error_cm'))} / {_num(b.get('p90_error_cm'))}",
        "calibration": calibration_cell(m.get("calibration", {})),
        "agreement": f"{_pct(maps.get('odometry', {}).get('agreement'))} / {_pct(true_map.get('agreement'))}",
        "occupied": f"{_pct(true_map.get('occupied_precision'))} / {_pct(true_map.get('occupied_recall'))}",
        "free_known": _pct(m.get("free_known_share")),
        "reliable": reliable,
        "reliable_avoidance": reliable_avoidance,
        "speed": f"{m['ranging_ms_per_frame']:.3f} / {m['mapping_ms_per_frame']:.3f}",
    }


def markdown_table(rows: Sequence[Dict[str, str]]) -> str:
    head = "| " + " | ".join(t for t, _ in COLUMNS) + " |"
    sep = "|" + "|".join("---" if k == "scenario" else "---:" for _, k in COLUMNS) + "|"
    body = ["| " + " | ".join(r[k] for _, k in COLUMNS) + " |" for r in rows]
    return "\n".join([head, sep, *body]) + "\n"


def _mean(values: List[float]) -> Optional[float]:
    v = [x for x in values if x is not None and math.isfinite(x)]
    return float(np.mean(v)) if v else None


def group_summary(records: Sequence[Dict[str, Any]]) -> Dict[str, Any]:
    """Pooled figures over scenarios: boundary columns pooled (error rate, point errors by
    range), other figures the mean over scenarios (map agreement, calibration max: the max)."""
    scores = [s for r in records for s in r["result"].column_scores]
    out: Dict[str, Any] = {
        "scenarios": len(records),
        "frames": sum(r["metrics"]["frames"] for r in records),
    }
    if scores:
        out["boundary"] = summarise_columns(scores).as_dict()
    ms = [r["metrics"] for r in records]
    cals = [m["calibration"] for m in ms if m.get("calibration", {}).get("status") == "measured"]
    out["calibration"] = (
        {
            "status": "measured",
            "max_cm": max(c["max_cm"] for c in cals),
            "rms_cm": float(np.sqrt(np.mean([c["rms_cm"] ** 2 for c in cals]))),
            **(
                {"covered_share": float(np.mean([c["covered_share"] for c in cals]))}
                if all("covered_share" in c for c in cals)
                else {}
            ),
        }
        if cals
        else (ms[0].get("calibration", {}) if ms else {})
    )
    out["map"] = {
        kind: {
            key: _mean([m.get("map", {}).get(kind, {}).get(key) for m in ms])
            for key in ("agreement", "occupied_precision", "occupied_recall")
        }
        for kind in ("odometry", "true_poses")
    }
    out["free_known_share"] = _mean([m.get("free_known_share") for m in ms])
    for key in ("reliable_local_map", "reliable_avoidance_map"):
        frames = [f for m in ms for f in m.get(key, {}).get("frames_per_view", [])]
        right = [f for m in ms for f in m.get(key, {}).get("frames_ranger_right", [])]
        out[key] = {
            "frames_per_view": frames,
            "median_frames": median_frames(frames),
            "views_never_reliable": sum(1 for f in frames if f is None),
            "max_frames_tried": max(
                (m.get(key, {}).get("max_frames_tried", 0) for m in ms), default=0
            ),
            "frames_ranger_right": right,
            "ranger_right_views": len(right),
            "median_frames_ranger_right": median_frames(right),
        }
    out["ranging_ms_per_frame"] = _mean([m["ranging_ms_per_frame"] for m in ms])
    out["mapping_ms_per_frame"] = _mean([m["mapping_ms_per_frame"] for m in ms])
    return out


def groups(records: Sequence[Dict[str, Any]]) -> Dict[str, List[Dict[str, Any]]]:
    out: Dict[str, List[Dict[str, Any]]] = {}
    for r in records:
        out.setdefault(r["scenario"].get("group", "dataset"), []).append(r)
    return dict(sorted(out.items(), key=lambda kv: (kv[0] != CARPET, kv[0])))


def range_table(summary: Dict[str, Any]) -> str:
    b = summary.get("boundary")
    if not b:
        return ""
    lines = ["| range | points | median cm | p90 cm |", "|---|---:|---:|---:|"]
    for band, v in b["by_range"].items():
        lines.append(f"| {band} | {v['points']} | {_num(v['median_cm'])} | {_num(v['p90_cm'])} |")
    return "\n".join(lines) + "\n"


def goals(carpet: Dict[str, Any], carpet_defaults: Optional[Dict[str, Any]]) -> str:
    """Where we stand against the issue's goals (carpet worlds)."""
    ref = carpet_defaults or carpet
    err = ref.get("boundary", {}).get("error_rate")
    cal = carpet.get("calibration", {})
    agr = ref.get("map", {}).get("true_poses", {}).get("agreement")
    rel = ref.get("reliable_local_map", {}).get("median_frames")
    rel_text = "-" if rel is None else (f"{rel:g}" if math.isfinite(rel) else "> 10")
    avoid = ref.get("reliable_avoidance_map", {})
    arel = avoid.get("median_frames_ranger_right")
    arel_text = (
        "-"
        if arel is None
        else (f"{arel:g}" if math.isfinite(arel) else "> 10")
        + f" ({avoid.get('ranger_right_views', 0)} views)"
    )

    def verdict(ok: Optional[bool]) -> str:
        return "n/a" if ok is None else ("met" if ok else "**missed**")

    cal_text = calibration_cell(cal)
    cal_ok = cal["max_cm"] <= 1.0 if cal.get("status") == "measured" else None
    rows = [
        (
            "boundary error rate, carpet, defaults",
            "<= 3 %",
            f"{_pct(err)} %",
            verdict(None if err is None else err <= 0.03),
        ),
        (
            "calibration max error within 3 m",
            "<= 1 cm",
            f"{cal_text} (max / RMS cm)",
            verdict(cal_ok),
        ),
        (
            "global map agreement, true poses, carpet defaults",
            ">= 97 %",
            f"{_pct(agr)} %",
            verdict(None if agr is None else agr >= 0.97),
        ),
        (
            "frames to a reliable local map (median; `run`'s local map, its own evidence)",
            "<= 2",
            rel_text,
            verdict(None if rel is None else rel <= 2),
        ),
        (
            "frames to a reliable avoidance map (median; views where the ranger is right)",
            "<= 2",
            arel_text,
            verdict(None if arel is None else arel <= 2),
        ),
    ]
    lines = ["| goal | target | measured | |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    return "\n".join(lines) + "\n"


def write_report(
    out: Path, records: Sequence[Dict[str, Any]], *, command: str, worst_pictures: int = 4
) -> Dict[str, Any]:
    """Writes ``report.md``, ``report.json`` and ``worst/*.png`` into ``out``; returns the JSON
    document."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rows = [row_cells(r["scenario"]["name"], r["metrics"]) for r in records]
    grouped = groups(records)
    summaries = {g: group_summary(rs) for g, rs in grouped.items()}
    carpet_defaults = [
        r
        for r in grouped.get(CARPET, [])
        if all(
            r["scenario"].get(k) == v
            for k, v in (("lighting", "normal"), ("noise", "default"), ("lens", "fisheye"))
        )
    ]
    default_summary = group_summary(carpet_defaults) if carpet_defaults else None
    md = [f"Command: `{command}`\n", "## Per scenario\n", markdown_table(rows)]
    md.append("\n## Per world group (carpet first; the others break an assumption of the paper)\n")
    md.append(markdown_table([row_cells(g, s) for g, s in summaries.items()]))
    if CARPET in summaries:
        md.append("\n## Carpet worlds: point error by true range\n")
        md.append(range_table(summaries[CARPET]))
        md.append("\n## Goals (carpet; boundary, map and local map at default settings)\n")
        md.append(goals(summaries[CARPET], default_summary))
    pictures = write_worst(out / "worst", records, max(worst_pictures, len(summaries)))
    if pictures:
        md.append("\n## Worst frames (circles: detected; white dashes: true boundary)\n")
        md.append("".join(f"- `{p.relative_to(out)}`: {why}\n" for p, why in pictures))
    text = "\n".join(md)
    write_atomic(out / "report.md", text)
    doc = {
        "command": command,
        "scenarios": [
            {"scenario": r["scenario"], "metrics": r["metrics"], "wall_s": r.get("wall_s")}
            for r in records
        ],
        "groups": summaries,
        "carpet_defaults": default_summary,
        "worst_pictures": [str(p.relative_to(out)) for p, _ in pictures],
    }
    write_atomic(out / "report.json", json.dumps(doc, indent=2, default=_json_default))
    return doc


def _json_default(x: Any) -> Any:
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (np.floating,)):
        return float(x)
    raise TypeError(type(x).__name__)


def write_worst(folder: Path, records: Sequence[Dict[str, Any]], count: int) -> List[tuple]:
    candidates = [
        (w["error_rate"], r["scenario"]["name"], w, r["scenario"].get("group"))
        for r in records
        for w in r["result"].worst
        if "image" in w
    ]
    candidates.sort(key=lambda c: -c[0])
    # The worst frame of every group first (so one failing group does not hide the others),
    # then the worst of the rest.
    chosen, seen = [], set()
    for c in candidates:
        if c[3] not in seen:
            seen.add(c[3])
            chosen.append(c)
    taken = {id(c) for c in chosen}
    chosen += [c for c in candidates if id(c) not in taken]
    out = []
    for rate, name, w, _ in chosen[:count]:
        scan = w["scan"]
        truth_rows = np.asarray(w["truth_rows"], dtype=float)[scan.columns.astype(np.intp)]
        picture = draw_scan_overlay(w["image"], scan, truth_rows=truth_rows)
        path = write_png(folder / f"{name}-frame{w['frame']:05d}.png", picture)
        out.append((path, f"{name}, frame {w['frame']}: {100 * rate:.1f} % of columns wrong"))
    return out
