"""Merging maps already made: the stored evidence of each (``map.evidence.npz`` beside its
``map.yaml``) summed into one map, written as ``floorscan run`` writes its map: ``map.yaml`` +
``map.pgm`` (map_server), ``map.png``, ``map.evidence.npz`` and ``summary.json``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np

from .._atomic import PathLike, write_atomic
from ..errors import DatasetError
from .evidence import EVIDENCE_SUFFIX, EvidenceMap, evidence_path, merge_evidence
from .grid import OccupancyGrid


def find_evidence(path: PathLike) -> Path:
    """The evidence file of a map: a ``.evidence.npz`` itself, the one beside a map_server
    YAML, or ``map.evidence.npz`` in a ``floorscan run`` output folder."""
    p = Path(path)
    if p.is_dir():
        candidate = p / ("map" + EVIDENCE_SUFFIX)
    elif p.name.endswith(EVIDENCE_SUFFIX):
        candidate = p
    elif p.suffix.lower() in (".yaml", ".yml"):
        candidate = evidence_path(p)
    else:
        raise DatasetError(f"{p}: give a map YAML, its {EVIDENCE_SUFFIX} or a run output folder")
    if not candidate.is_file():
        raise DatasetError(
            f"{p}: no evidence file {candidate.name} (maps from `floorscan run` have one; "
            "a map_server map alone cannot be merged exactly)"
        )
    return candidate


def cell_counts(ev: EvidenceMap) -> Dict[str, int]:
    """Free, occupied and known cells of the map the evidence makes (map_server thresholds
    of the evidence's options, as the grid classifies them)."""
    c = ev.clamped().astype(np.int32)
    logit = lambda p: math.log(p / (1.0 - p))  # noqa: E731
    occupied_at = math.ceil(1000 * logit(ev.occupied_threshold))
    free_at = math.floor(1000 * logit(ev.free_threshold))
    occupied = int(np.count_nonzero(c >= occupied_at))
    free = int(np.count_nonzero(c <= free_at))
    return {"free": free, "occupied": occupied, "known": free + occupied}


def describe(ev: EvidenceMap) -> Dict[str, object]:
    h, w = ev.values.shape
    return {
        "recordings": list(ev.recordings),
        "cells": cell_counts(ev),
        "width": w,
        "height": h,
        "origin_m": list(ev.origin_m),
        "cell_size_m": ev.cell_size_m,
    }


def write_merged(ev: EvidenceMap, out_dir: PathLike, *, summary: Dict[str, object]) -> Path:
    """Writes a merged evidence map as map_server map, PNG, evidence and summary."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if ev.values.size == 0:
        raise DatasetError("nothing to merge: every map is empty")
    grid = OccupancyGrid.from_evidence(ev)
    grid.save(out / "map.yaml")
    grid.to_png(out / "map.png")
    ev.save(out / ("map" + EVIDENCE_SUFFIX))
    full = {
        **summary,
        "merged": describe(ev),
        "clamping": "merged map = evidence summed exactly, clamped once (docs/fleet.md)",
        "outputs": ["map.yaml", "map.pgm", "map.png", "map" + EVIDENCE_SUFFIX, "summary.json"],
    }
    write_atomic(out / "summary.json", json.dumps(full, indent=2, default=float))
    return out


def merge_maps(inputs: Sequence[PathLike], out_dir: PathLike) -> EvidenceMap:
    """Merges maps made before (see :func:`find_evidence` for what ``inputs`` may be) into
    ``out_dir``; returns the merged evidence."""
    paths: List[Path] = [find_evidence(p) for p in inputs]
    maps = [EvidenceMap.load(p) for p in paths]
    merged = merge_evidence(maps)
    write_merged(
        merged,
        out_dir,
        summary={"inputs": [{"path": str(p), **describe(m)} for p, m in zip(paths, maps)]},
    )
    return merged
