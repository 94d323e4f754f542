"""Scoring the range sensor on real frames with hand-drawn floor masks, in image rows (no camera
geometry is known for such frames). Folder format (as ``../shared/data/floors``):
``images/<stem>.jpg|png`` and ``masks/<stem>.png`` (255 floor, 0 not floor), stems
``<clip>_f<frame>``; an optional ``floor_types.csv`` (``clip,floor_type``) names each clip's floor.

Per-column truth: scanning up from the bottom row, the first pixel that starts a run of 3
non-floor mask pixels is the boundary; a bottom row that is not floor is ``too_close``; floor to
the top is ``no_boundary``. A reading is right when its status matches and, for boundaries, its
row is within max(3 px, 1.25 % of the image height) of the truth.
"""

from __future__ import annotations

import csv
import re
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, Iterable, List, Optional, Sequence

import numpy as np

from ..errors import DatasetError
from ..ranging.ground_table import GroundTable
from .scoring import BOUNDARY, INVALID, NO_BOUNDARY, TOO_CLOSE

RUN_PX = 3
"""Non-floor mask pixels in a run that make the true boundary."""

KNOWN_FLOOR_TYPES = {
    "Library_01": "parquet and rugs",
    "Living_room_01": "parquet and rugs",
    "Living_room_02": "parquet and rugs",
    "mall_01": "glossy tiles",
    "parking_01": "concrete",
    "warehouse_01": "painted concrete",
}
"""Floor types of the clips of ``../shared/data/floors`` (its README); other folders name
theirs in ``floor_types.csv``, else the type is ``unknown``."""

_STEM = re.compile(r"^(?P<clip>.+)_f(?P<frame>\d+)$")


@dataclass(frozen=True)
class FloorFrame:
    stem: str
    clip: str
    frame: int
    image_path: Path
    mask_path: Path


def floor_mask_truth(mask: np.ndarray) -> tuple:
    """Per image column of a (H, W) floor mask (True or nonzero = floor): ``(status, rows)``,
    status codes (uint8; 0 boundary, 1 no_boundary, 2 too_close) and the boundary row v
    (float64, NaN where not a boundary), by the rule in the module docstring."""
    m = np.asarray(mask)
    if m.ndim != 2 or m.size == 0:
        raise DatasetError(f"a floor mask must be a non-empty (H, W) array, got shape {m.shape}")
    floor = m.astype(bool)[::-1]  # row k counts from the bottom
    h, w = floor.shape
    not_floor = ~floor
    run = not_floor.copy()
    for i in range(1, RUN_PX):
        run[: h - i] &= not_floor[i:]
        run[h - i :] = False
    has = run.any(axis=0)
    k = run.argmax(axis=0)
    status = np.where(has, BOUNDARY, NO_BOUNDARY).astype(np.uint8)
    rows = np.where(has, h - 1 - k, np.nan).astype(np.float64)
    too_close = not_floor[0]
    status[too_close] = TOO_CLOSE
    rows[too_close] = np.nan
    return status, rows


def row_tolerance_px(image_height: int) -> float:
    """max(3 px, 1.25 % of the image height)."""
    return max(3.0, 0.0125 * image_height)


def wrong_columns(
    status: np.ndarray,
    rows: np.ndarray,
    true_status: np.ndarray,
    true_rows: np.ndarray,
    image_height: int,
) -> np.ndarray:
    """Per column: wrong status (``invalid`` is always wrong), or a boundary row off by more
    than :func:`row_tolerance_px`."""
    s = np.asarray(status).astype(np.int64)
    t = np.asarray(true_status).astype(np.int64)
    both = (s == BOUNDARY) & (t == BOUNDARY)
    off = np.zeros(s.shape, bool)
    off[both] = np.abs(np.asarray(rows)[both] - np.asarray(true_rows)[both]) > row_tolerance_px(
        image_height
    )
    return (s != t) | (s == INVALID) | off


def list_floor_frames(folder) -> List[FloorFrame]:
    """The frames of a floor-mask folder, sorted by clip and frame number."""
    root = Path(folder)
    images, masks = root / "images", root / "masks"
    if not images.is_dir() or not masks.is_dir():
        raise DatasetError(f"{root} is not a floor-mask folder: it needs images/ and masks/")
    out = []
    for p in images.iterdir():
        if p.suffix.lower() not in (".jpg", ".jpeg", ".png"):
            continue
        m = masks / (p.stem + ".png")
        if not m.is_file():
            raise DatasetError(f"image {p.name} has no mask {m.name} in {masks}")
        g = _STEM.match(p.stem)
        clip, frame = (g["clip"], int(g["frame"])) if g else (p.stem, 0)
        out.append(FloorFrame(p.stem, clip, frame, p, m))
    if not out:
        raise DatasetError(f"no images in {images}")
    return sorted(out, key=lambda f: (f.clip, f.frame))


def floor_types(folder) -> Dict[str, str]:
    """Clip -> floor type: the folder's ``floor_types.csv`` over :data:`KNOWN_FLOOR_TYPES`."""
    types = dict(KNOWN_FLOOR_TYPES)
    p = Path(folder) / "floor_types.csv"
    if p.is_file():
        with p.open(newline="") as f:
            for row in csv.reader(f):
                if len(row) >= 2 and row[0] != "clip":
                    types[row[0].strip()] = row[1].strip()
    return types


def read_floor_frame(frame: FloorFrame) -> tuple:
    """(RGB uint8 (H, W, 3) image, boolean (H, W) floor mask)."""
    from PIL import Image

    with Image.open(frame.image_path) as im:
        rgb = np.asarray(im.convert("RGB"))
    with Image.open(frame.mask_path) as m:
        mask = np.asarray(m.convert("L")) > 127
    if mask.shape != rgb.shape[:2]:
        raise DatasetError(
            f"{frame.mask_path.name} is {mask.shape[1]} x {mask.shape[0]} but its image is "
            f"{rgb.shape[1]} x {rgb.shape[0]}"
        )
    return rgb, mask


# A ranger factory: (image_width, image_height) -> object with .scan(image, timestamp=) whose
# scans give rows and status codes; called once per clip (a model learned over a clip's frames
# carries over to its next frame, as on a robot).
RangerFactory = Callable[[int, int], object]


def image_row_table(image_width: int, image_height: int):
    """A ground table with ground at every pixel (x grows up the image), so rangers can run on
    frames without camera geometry and be scored in rows."""
    spacing = 8
    nu, nv = GroundTable.node_shape_for(
        image_width=image_width, image_height=image_height, spacing_px=spacing
    )
    v = np.arange(nv)[:, None] * spacing
    u = np.arange(nu)[None, :] * spacing
    x = 1.0 + (image_height - 1 - v) * 0.01 + 0 * u
    y = (image_width / 2.0 - u) * 0.001 + 0 * v
    return GroundTable.from_arrays(
        x.astype(float),
        y.astype(float),
        image_width=image_width,
        image_height=image_height,
        spacing_px=spacing,
    )


@dataclass
class LoadedFrame:
    """A frame decoded once: its RGB image and per-column truth."""

    frame: FloorFrame
    rgb: np.ndarray
    true_status: np.ndarray
    true_rows: np.ndarray


def load_floor_frames(
    frames: Sequence[FloorFrame], *, trim_mask_bottom: int = 0
) -> List[LoadedFrame]:
    """Decodes frames and their truth. ``trim_mask_bottom`` > 0 is a diagnostic, not the rule:
    the mask's bottom N rows take the values of the row above them (hand-drawn masks resized
    to the frame often lose their bottom rows, which the rule then reads as ``too_close``)."""
    if (
        isinstance(trim_mask_bottom, bool)
        or not isinstance(trim_mask_bottom, int)
        or trim_mask_bottom < 0
    ):
        raise DatasetError(f"trim_mask_bottom must be an integer >= 0, got {trim_mask_bottom!r}")
    out = []
    for f in frames:
        rgb, mask = read_floor_frame(f)
        n = trim_mask_bottom
        if n:
            if n >= mask.shape[0]:
                raise DatasetError(f"trim_mask_bottom {n} leaves nothing of {f.mask_path.name}")
            mask = mask.copy()
            mask[-n:] = mask[-n - 1]
        ts, tr = floor_mask_truth(mask)
        out.append(LoadedFrame(f, rgb, ts, tr))
    return out


def range_floor_frames(loaded: Sequence[LoadedFrame], make_ranger: RangerFactory):
    """Ranges every frame (one ranger per clip and image size, frames in order, so a model
    learned over a clip carries over as on a robot). Yields ``(frame, columns, scan)``:
    ``columns`` the sampled image columns (intp), ``scan`` the :class:`Scan`."""
    for _clip, group in _by_clip(loaded):
        ranger, size = None, None
        for lf in group:
            h, w = lf.rgb.shape[:2]
            if ranger is None or size != (w, h):
                ranger, size = make_ranger(w, h), (w, h)
            scan = ranger.scan(lf.rgb, timestamp=float(lf.frame.frame))
            yield lf, scan.columns.astype(np.intp), scan


def score_floor_frames(
    loaded: Sequence[LoadedFrame], make_ranger: RangerFactory
) -> Dict[str, tuple]:
    """Ranges every frame (:func:`range_floor_frames`); per clip: (wrong columns, columns,
    truth status counts (4,), frames)."""
    out: Dict[str, list] = {}
    for lf, cols, scan in range_floor_frames(loaded, make_ranger):
        h = lf.rgb.shape[0]
        bad = wrong_columns(
            scan.status_codes, scan.rows, lf.true_status[cols], lf.true_rows[cols], h
        )
        acc = out.setdefault(lf.frame.clip, [0, 0, np.zeros(4, np.int64), 0])
        acc[0] += int(bad.sum())
        acc[1] += bad.size
        acc[2] += np.bincount(lf.true_status[cols], minlength=4)
        acc[3] += 1
    return {clip: tuple(acc) for clip, acc in out.items()}


def summarise_floor_scores(
    per_clip: Dict[str, tuple], types: Optional[Dict[str, str]] = None
) -> Dict[str, object]:
    """``{"overall": {...}, "clips": {clip: {...}}, "floor_types": {type: {...}}}``, each with
    ``frames``, ``columns``, ``error_rate`` and the truth's status mix."""
    types = types or {}

    def summary(clips: Iterable[str]) -> Dict[str, object]:
        clips = list(clips)
        wrong = sum(per_clip[c][0] for c in clips)
        n = sum(per_clip[c][1] for c in clips)
        m = sum((per_clip[c][2] for c in clips), np.zeros(4, np.int64))
        return {
            "frames": sum(per_clip[c][3] for c in clips),
            "columns": int(n),
            "error_rate": wrong / n if n else float("nan"),
            "truth_boundary": int(m[BOUNDARY]),
            "truth_no_boundary": int(m[NO_BOUNDARY]),
            "truth_too_close": int(m[TOO_CLOSE]),
        }

    by_type: Dict[str, List[str]] = defaultdict(list)
    for c in per_clip:
        by_type[types.get(c, "unknown")].append(c)
    return {
        "overall": summary(per_clip),
        "clips": {c: dict(summary([c]), floor_type=types.get(c, "unknown")) for c in per_clip},
        "floor_types": {t: summary(cs) for t, cs in sorted(by_type.items())},
    }


def evaluate_floor_masks(
    frames: Sequence[FloorFrame],
    make_ranger: RangerFactory,
    *,
    types: Optional[Dict[str, str]] = None,
) -> Dict[str, object]:
    """Loads, ranges and scores frames: :func:`summarise_floor_scores` of
    :func:`score_floor_frames`."""
    return summarise_floor_scores(score_floor_frames(load_floor_frames(frames), make_ranger), types)


def _by_clip(loaded: Sequence[LoadedFrame]):
    groups: Dict[str, List[LoadedFrame]] = defaultdict(list)
    for lf in loaded:
        groups[lf.frame.clip].append(lf)
    for clip in sorted(groups):
        yield clip, sorted(groups[clip], key=lambda lf: lf.frame.frame)


def format_floor_report(result: Dict[str, object], *, title: str) -> str:
    """A Markdown table per clip and per floor type."""
    lines = [
        f"## {title}",
        "",
        "| clip | floor | frames | columns | wrong | truth b / nb / tc |",
        "|---|---|---:|---:|---:|---|",
    ]
    for c, s in sorted(result["clips"].items()):
        lines.append(
            f"| {c} | {s['floor_type']} | {s['frames']} | {s['columns']} | "
            f"{100 * s['error_rate']:.1f} % | {s['truth_boundary']} / {s['truth_no_boundary']} / "
            f"{s['truth_too_close']} |"
        )
    o = result["overall"]
    lines.append(
        f"| **all** | | {o['frames']} | {o['columns']} | **{100 * o['error_rate']:.1f} %** | "
        f"{o['truth_boundary']} / {o['truth_no_boundary']} / {o['truth_too_close']} |"
    )
    lines += ["", "| floor type | frames | columns | wrong |", "|---|---:|---:|---:|"]
    for t, s in result["floor_types"].items():
        lines.append(f"| {t} | {s['frames']} | {s['columns']} | {100 * s['error_rate']:.1f} % |")
    return "\n".join(lines) + "\n"
