"""ROS map_server maps (a public contract, see docs/formats.md): a YAML file and an 8-bit
image (PGM written; PGM, PNG or any Pillow-readable image read).

YAML keys: ``image`` (path relative to the YAML), ``resolution`` [m/pixel], ``origin``
``[x, y, yaw]`` (world pose of the lower-left pixel's corner; yaw must be 0 here), ``negate``
(0/1), ``occupied_thresh``, ``free_thresh``, and optionally ``mode`` (``trinary``, the default,
``scale`` or ``raw``). Pixel value v gives p = (255 - v) / 255 (v / 255 when negated); with
``trinary``, p > occupied_thresh is occupied, p < free_thresh free, anything else unknown.

Writing follows map_saver: occupied 0, free 254, unknown 205, thresholds 0.65 / 0.196, image
row 0 at the top (highest y). ``mode="scale"`` writes grey levels 255 (1 - p) instead, keeping
probabilities to 1/255 (unknown cells then read back as p = 0.5 +- 0.002).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, Dict, Optional

import numpy as np

from ._atomic import PathLike, write_atomic
from .errors import FileFormatError, OptionError

MODES = ("trinary", "scale", "raw")
TRINARY_FREE, TRINARY_UNKNOWN, TRINARY_OCCUPIED = 254, 205, 0


def save_map(grid, path: PathLike, *, mode: str = "trinary", extent=None) -> Path:
    """Writes ``grid`` (an OccupancyGrid or LocalMap) as ``path`` (YAML) plus a PGM of the same
    stem beside it, each atomically (PGM first). Returns the YAML path."""
    if mode not in ("trinary", "scale"):
        raise OptionError(f"invalid option `mode`: can write 'trinary' or 'scale', got {mode!r}")
    yaml_path = Path(path)
    if yaml_path.suffix.lower() not in (".yaml", ".yml"):
        raise OptionError(f"map path must end in .yaml or .yml, got {str(path)!r}")
    e = extent or grid.extent
    if e.width == 0 or e.height == 0:
        raise OptionError("the map is empty: nothing to save (insert data first or pass an extent)")
    # Both styles of GridViews.to_image are exactly map_server's pixel values.
    pixels = grid.to_image(style="trinary" if mode == "trinary" else "probability", extent=e)
    pgm_path = yaml_path.with_suffix(".pgm")
    header = (
        f"P5\n# CREATOR: floorscan {e.cell_size_m!r} m/pix\n{e.width} {e.height}\n255\n".encode(
            "ascii"
        )
    )
    write_atomic(pgm_path, header + pixels.tobytes())
    ox, oy = e.origin_m
    text = (
        f"image: {pgm_path.name}\n"
        f"mode: {mode}\n"
        f"resolution: {e.cell_size_m!r}\n"
        f"origin: [{ox!r}, {oy!r}, 0.0]\n"
        "negate: 0\n"
        "occupied_thresh: 0.65\n"
        "free_thresh: 0.196\n"
    )
    write_atomic(yaml_path, text)
    return yaml_path


def read_map_yaml(path: PathLike) -> Dict[str, Any]:
    """The keys of a map_server YAML file (flat ``key: value`` mapping; values are numbers,
    strings or ``[a, b, c]`` lists), checked; errors name the file and line."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise FileFormatError(f"cannot read map YAML {path}: {e}") from None
    raw: Dict[str, Any] = {}
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = _strip_comment(line).strip()
        if not stripped or stripped in ("---", "..."):
            continue
        m = re.fullmatch(r"([A-Za-z_][A-Za-z0-9_]*)\s*:\s*(.*)", stripped)
        if not m or line[:1].isspace():
            raise FileFormatError(f"{path}:{lineno}: expected 'key: value', got {line.strip()!r}")
        raw[m.group(1)] = (_scalar_or_list(m.group(2), path, lineno), lineno)
    return _check_keys(raw, path)


def _strip_comment(line: str) -> str:
    quote = None
    for i, ch in enumerate(line):
        if ch in "'\"":
            quote = None if quote == ch else (quote or ch)
        elif ch == "#" and quote is None and (i == 0 or line[i - 1].isspace()):
            return line[:i]
    return line


def _scalar_or_list(text: str, path: Path, lineno: int):
    text = text.strip()
    if text.startswith("["):
        if not text.endswith("]"):
            raise FileFormatError(f"{path}:{lineno}: unterminated list {text!r}")
        items = [t.strip() for t in text[1:-1].split(",")]
        return [_scalar(t, path, lineno) for t in items if t]
    return _scalar(text, path, lineno)


def _scalar(text: str, path: Path, lineno: int):
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def _check_keys(raw: Dict[str, Any], path: Path) -> Dict[str, Any]:
    def get(key: str, default=None, required: bool = False):
        if key not in raw:
            if required:
                raise FileFormatError(f"{path}: missing required key `{key}`")
            return default, 0
        return raw[key]

    def number(key: str, default=None, required: bool = False) -> float:
        v, line = get(key, default, required)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise FileFormatError(f"{path}:{line}: `{key}` must be a finite number, got {v!r}")
        return float(v)

    image, line = get("image", required=True)
    if not isinstance(image, str) or not image:
        raise FileFormatError(f"{path}:{line}: `image` must be a file name, got {image!r}")
    resolution = number("resolution", required=True)
    if resolution <= 0:
        raise FileFormatError(
            f"{path}:{raw['resolution'][1]}: `resolution` must be > 0, got {resolution}"
        )
    origin, line = get("origin", required=True)
    if not (
        isinstance(origin, list)
        and len(origin) == 3
        and all(isinstance(v, (int, float)) and math.isfinite(v) for v in origin)
    ):
        raise FileFormatError(f"{path}:{line}: `origin` must be [x, y, yaw], got {origin!r}")
    if origin[2] != 0:
        raise FileFormatError(
            f"{path}:{line}: rotated map origins (yaw {origin[2]}) are not supported"
        )
    negate, line = get("negate", 0)
    if negate not in (0, 1):
        raise FileFormatError(f"{path}:{line}: `negate` must be 0 or 1, got {negate!r}")
    occ = number("occupied_thresh", 0.65)
    free = number("free_thresh", 0.196)
    if not 0.0 <= free < occ <= 1.0:
        raise FileFormatError(
            f"{path}: need 0 <= free_thresh < occupied_thresh <= 1, got {free} and {occ}"
        )
    mode, line = get("mode", "trinary")
    if mode not in MODES:
        raise FileFormatError(f"{path}:{line}: `mode` must be one of {MODES}, got {mode!r}")
    return {
        "image": path.parent / image,
        "resolution": resolution,
        "origin": (float(origin[0]), float(origin[1])),
        "negate": int(negate),
        "occupied_thresh": occ,
        "free_thresh": free,
        "mode": mode,
    }


def read_map_image(path: PathLike) -> tuple:
    """(grey (H, W) float64 0..255 with row 0 at the top, alpha (H, W) or None). Colour pixels
    are the mean of their channels, as map_server does."""
    from PIL import UnidentifiedImageError

    from .errors import ImageError
    from .image_io import _decoded, open_image

    try:
        with open_image(path, f"map image {path}") as im:
            _decoded(im, str(path))
            if im.mode in ("RGBA", "LA", "PA") or "transparency" in im.info:
                rgba = np.asarray(im.convert("RGBA"), dtype=np.float64)
                return rgba[..., :3].mean(axis=2), rgba[..., 3]
            if im.mode == "L":
                return np.asarray(im, dtype=np.float64), None
            return np.asarray(im.convert("RGB"), dtype=np.float64).mean(axis=2), None
    except (OSError, UnidentifiedImageError, ImageError) as e:
        raise FileFormatError(f"cannot read map image {path}: {e}") from None


def load_map(path: PathLike, *, grow: bool = False, **options):
    """Reads a map_server map into an :class:`~floorscan.OccupancyGrid` whose lattice is the
    image's: cell (0, 0) is the bottom-left pixel, at the YAML's origin. The grid has the
    image's fixed bounds, or grows (``grow=True``) if more data is to be added around it.
    ``options`` are passed to OccupancyGrid (``cell_size_m``, ``origin_m`` and ``bounds_m``
    come from the file). Occupied pixels get the upper clamp, free ones the lower clamp,
    unknown ones 0; in ``scale`` mode every pixel's probability is kept (clamped); in ``raw``
    mode pixel values 0..100 are probabilities in percent and others unknown."""
    from .grid import OccupancyGrid

    meta = read_map_yaml(path)
    for key in ("cell_size_m", "origin_m", "bounds_m"):
        if key in options:
            raise OptionError(f"`{key}` comes from the map file; do not pass it")
    grey, alpha = read_map_image(meta["image"])
    res, (ox, oy) = meta["resolution"], meta["origin"]
    h, w = grey.shape
    bounds = None
    if not grow:
        # A quarter cell inside the image's edges: exactly its cells, whatever the rounding.
        bounds = (
            (ox + 0.25 * res, oy + 0.25 * res),
            (ox + (w - 0.25) * res, oy + (h - 0.25) * res),
        )
    grid = OccupancyGrid(cell_size_m=res, origin_m=(ox, oy), bounds_m=bounds, **options)
    lo, hi, _, _ = grid._native.limits()
    values = _pixels_to_units(grey, alpha, meta, lo, hi)
    grid.write_raw(np.ascontiguousarray(values[::-1]), x_cell=0, y_cell=0)
    return grid


def _pixels_to_units(
    grey: np.ndarray, alpha: Optional[np.ndarray], meta: Dict[str, Any], lo: int, hi: int
) -> np.ndarray:
    """Map server's interpretation of each pixel, as int16 log-odds units (row 0 at the top)."""
    mode = meta["mode"]
    out = np.zeros(grey.shape, np.int16)
    if mode == "raw":
        known = (grey >= 0) & (grey <= 100)
        p = np.clip(grey / 100.0, 1e-9, 1 - 1e-9)
        out[known] = np.clip(np.rint(1000.0 * np.log(p / (1 - p))), lo, hi)[known]
        return out
    p = grey / 255.0 if meta["negate"] else (255.0 - grey) / 255.0
    occupied = p > meta["occupied_thresh"]
    free = p < meta["free_thresh"]
    if mode == "trinary":
        out[occupied] = hi
        out[free] = lo
    else:  # scale: keep the probability
        pc = np.clip(p, 1e-9, 1 - 1e-9)
        out[:] = np.clip(np.rint(1000.0 * np.log(pc / (1 - pc))), lo, hi)
    if alpha is not None:
        out[alpha == 0] = 0
    return out
