"""Reading images as greyscale numpy arrays, and checking arrays handed to floorscan."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._atomic import PathLike, temp_path_for
from .errors import ImageError, ImageTypeError


def as_grey(image) -> np.ndarray:
    """Checks an image and returns it as a (H, W) uint8 or uint16 array (no copy if it
    already is one). Colour (H, W, 3) or (H, W, 4) arrays are converted with ITU-R BT.601 luma
    weights (channels taken as RGB); float images are rejected (their scale is ambiguous)."""
    if not isinstance(image, np.ndarray):
        raise ImageTypeError(f"image must be a numpy array, got {type(image).__name__}")
    if image.dtype not in (np.uint8, np.uint16):
        raise ImageTypeError(f"image dtype must be uint8 or uint16, got {image.dtype}")
    if image.ndim == 3 and image.shape[2] in (3, 4):
        rgb = image[..., :3].astype(np.float32)
        grey = rgb @ np.array([0.299, 0.587, 0.114], dtype=np.float32)
        image = np.clip(np.rint(grey), 0, np.iinfo(image.dtype).max).astype(image.dtype)
    elif image.ndim == 3 and image.shape[2] == 1:
        image = image[..., 0]
    if image.ndim != 2:
        raise ImageError(
            f"image must be (H, W) greyscale or (H, W, 3) colour, got shape {image.shape}"
        )
    if image.shape[0] == 0 or image.shape[1] == 0:
        raise ImageError(f"image is empty: shape {image.shape} (H, W)")
    return image


def read_grey(path: PathLike) -> np.ndarray:
    """Reads an image file (PNG, JPEG, ... 8 or 16 bit) as a (H, W) uint8 or uint16 array."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as im:
            im.load()
            if im.mode in ("I;16", "I;16B", "I;16L", "I"):
                arr = np.asarray(im)
                return np.clip(arr, 0, 65535).astype(np.uint16) if arr.dtype != np.uint16 else arr
            return np.asarray(im.convert("L"))
    except FileNotFoundError:
        raise ImageError(f"image file not found: {path}") from None
    except (UnidentifiedImageError, OSError, SyntaxError) as e:
        raise ImageError(f"cannot read image {path}: {e}") from None


def read_rgb(path: PathLike) -> np.ndarray:
    """Reads an image file as a (H, W, 3) uint8 RGB array (grey files give equal channels)."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as im:
            return np.asarray(im.convert("RGB"))
    except FileNotFoundError:
        raise ImageError(f"image file not found: {path}") from None
    except (UnidentifiedImageError, OSError, SyntaxError) as e:
        raise ImageError(f"cannot read image {path}: {e}") from None


def write_png(path: PathLike, image: np.ndarray) -> Path:
    """Writes a uint8 grey (H, W) or colour (H, W, 3) image as PNG, atomically."""
    from PIL import Image

    target = Path(path)
    tmp = temp_path_for(target, ".png")
    try:
        Image.fromarray(np.ascontiguousarray(image)).save(tmp, format="PNG")
        tmp.replace(target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return target
