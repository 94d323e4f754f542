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
import yaml
from PIL import Image, UnidentifiedImageError

from .._atomic import PathLike, write_atomic, write_atomic_with
from .._native import mapping as _native_mapping
from ..errors import FileFormatError, ImageError, OptionError
from .image_io import _decoded, open_image

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
    return write_map_files(
        yaml_path, pixels, cell_size_m=e.cell_size_m, origin_m=e.origin_m, mode=mode
    )


def write_map_files(
    path: PathLike, pixels: np.ndarray, *, cell_size_m: float, origin_m, mode: str = "trinary"
) -> Path:
    """Writes map_server's two files: ``pixels`` ((H, W) uint8, row 0 at the top) as an 8-bit
    PGM (Pillow) beside ``path`` (its YAML), each atomically, PGM first. Returns the YAML
    path."""
    yaml_path = Path(path)
    pgm_path = yaml_path.with_suffix(".pgm")
    image = Image.fromarray(np.ascontiguousarray(pixels, dtype=np.uint8), mode="L")
    write_atomic_with(pgm_path, lambda f: image.save(f, format="PPM"), suffix=".pgm")
    ox, oy = origin_m
    text = (
        f"image: {pgm_path.name}\n"
        f"mode: {mode}\n"
        f"resolution: {float(cell_size_m)!r}\n"
        f"origin: [{float(ox)!r}, {float(oy)!r}, 0.0]\n"
        "negate: 0\n"
        "occupied_thresh: 0.65\n"
        "free_thresh: 0.196\n"
    )
    write_atomic(yaml_path, text)
    return yaml_path


def read_map_yaml(path: PathLike) -> Dict[str, Any]:
    """The keys of a map_server YAML file (PyYAML's safe loader), checked; errors name the file
    and line. Numbers written as YAML 1.2 / yaml-cpp read them (``5e-2`` too)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise FileFormatError(f"cannot read map YAML {path}: {e}") from None
    try:
        loader = yaml.SafeLoader(text)  # parsed once: the nodes give the lines, then the data
        try:
            node = loader.get_single_node()
            data = loader.construct_document(node) if node is not None else None
        finally:
            loader.dispose()
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark is not None else str(path)
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise FileFormatError(f"{where}: invalid YAML: {problem}") from None
    if not isinstance(data, dict) or not isinstance(node, yaml.MappingNode):
        raise FileFormatError(f"{path}: expected 'key: value' lines (a YAML mapping)")
    lines = {
        k.value: k.start_mark.line + 1 for k, _ in node.value if isinstance(k, yaml.ScalarNode)
    }
    raw = {str(k): (_number_text(v), lines.get(str(k), 0)) for k, v in data.items()}
    return _check_keys(raw, path)


def _number_text(v: Any) -> Any:
    """PyYAML (YAML 1.1) reads ``5e-2`` as a string; yaml-cpp, which map_server uses, as a
    number: numeric strings and lists of them become numbers."""
    if isinstance(v, list):
        return [_number_text(x) for x in v]
    if isinstance(v, str) and re.fullmatch(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", v.strip()):
        return float(v)
    return v


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


def pixels_to_units(
    grey: np.ndarray, alpha: Optional[np.ndarray], meta: Dict[str, Any], lo: int, hi: int
) -> np.ndarray:
    """map_server's interpretation of each pixel, as int16 log-odds [1/1000 nat] between the
    map's clamps ``lo`` and ``hi`` (row 0 at the top, as in the image). Occupied pixels get
    ``hi``, free ones ``lo``, unknown ones 0; in ``scale`` mode every pixel's probability is
    kept (clamped); in ``raw`` mode pixel values 0..100 are probabilities in percent and
    others unknown."""
    mode = meta["mode"]
    out = np.zeros(grey.shape, np.int16)
    if mode == "raw":
        known = (grey >= 0) & (grey <= 100)
        out[known] = _units(grey / 100.0, lo, hi)[known]
        return out
    p = grey / 255.0 if meta["negate"] else (255.0 - grey) / 255.0
    occupied = p > meta["occupied_thresh"]
    free = p < meta["free_thresh"]
    if mode == "trinary":
        out[occupied] = hi
        out[free] = lo
    else:  # scale: keep the probability
        out[:] = _units(p, lo, hi)
    if alpha is not None:
        out[alpha == 0] = 0
    return out


def _units(p: np.ndarray, lo: int, hi: int) -> np.ndarray:
    """Stored log-odds units of probabilities (the core's conversion, as
    ``floorscan.mapping.log_odds.units_from_probabilities``: a file format reads maps without
    depending on the mapping stage)."""
    return _native_mapping.units_from_probabilities(
        np.asarray(p, dtype=np.float64), int(lo), int(hi)
    )
