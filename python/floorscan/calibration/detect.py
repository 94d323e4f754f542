"""Finding the pattern's points in the image, and matching them to the pattern.

Checkerboards: OpenCV (``findChessboardCornersSB``, falling back to ``findChessboardCorners`` +
``cornerSubPix``). Line grids: :mod:`.lines`. Either gives a lattice of image points in an
unknown orientation; :func:`.lattice.label_lattice` matches it to the pattern's (i across, j away) from
geometry alone: the pattern's away axis runs up the image and its across axis left to right
(both turned by the pattern's yaw), so a detection that comes out flipped or rotated cannot mirror
the table.
"""

from __future__ import annotations

from typing import Optional, Tuple

import cv2
import numpy as np

from ..errors import CalibrationError
from ..formats.image_io import as_grey
from .lattice import Detection, label_lattice
from .lines import find_line_crossings
from .pattern import Pattern, PatternKind

MIN_CONTRAST = 24
"""Least spread of grey levels (1st to 99th percentile, 8-bit) worth searching for a pattern."""


def to_uint8(image: np.ndarray) -> np.ndarray:
    """A (H, W) uint8 grey image (16-bit images scaled by their own range)."""
    grey = as_grey(image)
    if grey.dtype == np.uint16:
        lo, hi = np.percentile(grey, [0.1, 99.9])
        scale = 255.0 / max(hi - lo, 1.0)
        grey = np.clip((grey.astype(np.float64) - lo) * scale, 0, 255).astype(np.uint8)
    return np.ascontiguousarray(grey)


def check_exposure(grey: np.ndarray) -> None:
    """Raises CalibrationError for an image with too little contrast to find anything in."""
    lo, hi = np.percentile(grey, [1, 99])
    if hi - lo < MIN_CONTRAST:
        what = "too dark" if hi < 64 else ("overexposed" if lo > 192 else "very low in contrast")
        raise CalibrationError(
            f"the calibration image is {what} (grey levels {lo:.0f}..{hi:.0f} from the 1st to the "
            f"99th percentile): check the exposure and lighting, and that the lens cap is off"
        )


def detect(image: np.ndarray, pattern: Pattern) -> Detection:
    """Finds ``pattern``'s inner corners (crossings) in ``image`` ((H, W) grey, uint8 or
    uint16) and matches them to the pattern. Raises :class:`floorscan.CalibrationError` when
    the pattern is not found (saying how many points were found and what to check)."""
    grey = to_uint8(image)
    check_exposure(grey)
    if pattern.kind is PatternKind.CHECKERBOARD:
        lattice, method = find_checkerboard(grey, pattern.counts)
        return label_lattice(lattice, pattern, method)
    return find_line_crossings(grey, pattern)


# --- checkerboards ----------------------------------------------------------------------
def find_checkerboard(grey: np.ndarray, counts: Tuple[int, int]) -> Tuple[np.ndarray, str]:
    """Inner corners of a checkerboard of ``counts`` (across, away): a (counts[1], counts[0],
    2) lattice of (u, v) [px] in OpenCV's order (which corner comes first is arbitrary)."""
    if min(counts) < 3:
        raise CalibrationError(
            f"a checkerboard needs at least 3 inner corners each way for OpenCV's detector, "
            f"the pattern says {counts[0]} x {counts[1]}"
        )
    size = (int(counts[0]), int(counts[1]))
    norm = cv2.CALIB_CB_NORMALIZE_IMAGE
    lattice, method = None, ""
    # Cheapest first. The ACCURACY variant (an upsampled search) and the classic detector
    # without its quad filter find boards the others miss in a 180-degree fisheye's corners.
    exhaustive = norm | cv2.CALIB_CB_EXHAUSTIVE
    for flags in (norm, exhaustive, exhaustive | cv2.CALIB_CB_ACCURACY):
        ok, corners = cv2.findChessboardCornersSB(grey, size, flags=flags)
        if ok:
            lattice = corners.reshape(size[1], size[0], 2).astype(np.float64)
            method = "findChessboardCornersSB + cornerSubPix"
            break
    if lattice is None:
        adaptive = cv2.CALIB_CB_ADAPTIVE_THRESH | norm
        for flags in (adaptive | cv2.CALIB_CB_FILTER_QUADS, adaptive):
            ok, corners = cv2.findChessboardCorners(grey, size, flags=flags)
            if ok:
                lattice = corners.reshape(size[1], size[0], 2).astype(np.float64)
                method = "findChessboardCorners + cornerSubPix"
                break
        if lattice is None:
            raise CalibrationError(_not_found_message(grey, size))
    board = _largest_board(grey)
    if board is not None and board[0] * board[1] > size[0] * size[1]:
        raise CalibrationError(
            f"the image shows a checkerboard of {board[0]} x {board[1]} inner corners, the "
            f"pattern file says {size[0]} x {size[1]}: check `inner_corners` (inner corners, one "
            f"fewer than squares each way)"
        )
    return refine_corners(grey, lattice), method


def _largest_board(grey: np.ndarray) -> Optional[Tuple[int, int]]:
    """(columns, rows) of inner corners of the largest board OpenCV finds, None if none."""
    try:
        ok, corners, meta = cv2.findChessboardCornersSBWithMeta(
            grey, (3, 3), flags=cv2.CALIB_CB_NORMALIZE_IMAGE | cv2.CALIB_CB_LARGER
        )
    except cv2.error:  # pragma: no cover - OpenCV without the LARGER flag
        return None
    if not ok or corners is None or meta is None:
        return None
    n = len(corners.reshape(-1, 2))
    rows = int(np.count_nonzero(np.any(meta > 0, axis=1)))
    cols = int(np.count_nonzero(np.any(meta > 0, axis=0)))
    # The meta grid counts squares around the corners; report the corners' own grid.
    if rows * cols == n:
        return cols, rows
    for c in range(1, n + 1):
        if n % c == 0 and abs(c - cols) <= 1 and abs(n // c - rows) <= 1:
            return c, n // c
    return None


def local_spacing(lattice: np.ndarray) -> np.ndarray:
    """Distance [px] from each lattice point to its nearest lattice neighbour, (rows, cols)."""
    rows, cols = lattice.shape[:2]
    best = np.full((rows, cols), np.inf)
    for axis in (0, 1):
        d = np.linalg.norm(np.diff(lattice, axis=axis), axis=-1)
        d = np.where(np.isfinite(d), d, np.inf)
        if axis == 0:
            best[1:] = np.minimum(best[1:], d)
            best[:-1] = np.minimum(best[:-1], d)
        else:
            best[:, 1:] = np.minimum(best[:, 1:], d)
            best[:, :-1] = np.minimum(best[:, :-1], d)
    return best


def refine_corners(
    grey: np.ndarray,
    lattice: np.ndarray,
    *,
    fraction: float = 0.3,
    spacing: Optional[np.ndarray] = None,
) -> np.ndarray:
    """Sub-pixel saddle points (``cornerSubPix``) near each lattice point, each with a window
    of ``fraction`` of its distance to the nearest neighbour (half-width 2..12 px), so windows
    stay clear of the next corner where the board is foreshortened."""
    out = lattice.copy()
    if spacing is None:
        spacing = local_spacing(lattice)
    criteria = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 60, 0.001)
    for r, c in zip(*np.nonzero(np.all(np.isfinite(lattice), axis=-1))):
        gap = spacing[r, c]
        half = int(np.clip(round(fraction * gap), 2, 12)) if np.isfinite(gap) else 3
        pt = lattice[r, c].reshape(1, 1, 2).astype(np.float32)
        cv2.cornerSubPix(grey, pt, (half, half), (-1, -1), criteria)
        moved = float(np.hypot(*(pt.reshape(2) - lattice[r, c])))
        if moved <= 0.5 * half + 1.0:  # a jump means the window saw something else
            out[r, c] = pt.reshape(2)
    return out


def _not_found_message(grey: np.ndarray, size: Tuple[int, int]) -> str:
    board = _largest_board(grey)
    if board is None:
        what = "no checkerboard corners found"
    else:
        what = f"found a board of {board[0]} x {board[1]} inner corners"
    return (
        f"checkerboard of {size[0]} x {size[1]} inner corners not found ({what}; expected "
        f"{size[0] * size[1]} corners): check `inner_corners` in the pattern file (inner corners, "
        f"one fewer than squares each way), that the whole board with a light border is in the "
        f"image, and that the image is in focus and evenly lit"
    )
