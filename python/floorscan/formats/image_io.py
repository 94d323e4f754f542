"""Reading images as greyscale numpy arrays, and checking arrays handed to floorscan."""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

import numpy as np

from .._atomic import PathLike, deferred_signals, discard_temporary, temp_path_for
from ..errors import ImageError, ImageTooLargeError, ImageTypeError, OptionError
from .png import is_png, max_png_file_bytes, png_to_grey


def as_grey(image) -> np.ndarray:
    """Checks an image and returns it as a (H, W) uint8 or uint16 array (no copy if it
    already is one). Colour (H, W, 3) or (H, W, 4) arrays are converted with ITU-R BT.601 luma
    weights (channels taken as RGB); float images are rejected (their scale is ambiguous)."""
    if not isinstance(image, np.ndarray):
        raise ImageTypeError(f"image must be a numpy array, got {type(image).__name__}")
    if image.dtype not in (np.uint8, np.uint16):
        raise ImageTypeError(f"image dtype must be uint8 or uint16, got {image.dtype}")
    if image.ndim == 3 and image.shape[2] in (3, 4):
        # OpenCV's fixed-point BT.601 (8x numpy's float product at 640 x 480), loaded on the
        # first colour image: importing it costs `import floorscan` 120 ms otherwise.
        import cv2

        code = cv2.COLOR_RGB2GRAY if image.shape[2] == 3 else cv2.COLOR_RGBA2GRAY
        image = cv2.cvtColor(np.ascontiguousarray(image), code)
    elif image.ndim == 3 and image.shape[2] == 1:
        image = image[..., 0]
    if image.ndim != 2:
        raise ImageError(
            f"image must be (H, W) greyscale or (H, W, 3) colour, got shape {image.shape}"
        )
    if image.shape[0] == 0 or image.shape[1] == 0:
        raise ImageError(f"image is empty: shape {image.shape} (H, W)")
    return image


DEFAULT_MAX_IMAGE_PIXELS = 1 << 26
"""Default of ``[limits] max_image_pixels``: 67 M pixels (8192 x 8192), about 200 MB decoded
as RGB. Larger images (decompression bombs among them) are refused before they are decoded."""

_max_image_pixels = DEFAULT_MAX_IMAGE_PIXELS


def set_max_image_pixels(pixels: int) -> None:
    """Sets the largest image (width x height) any reader decodes (``[limits]
    max_image_pixels``); ``floorscan run`` sets it from its configuration."""
    global _max_image_pixels
    _max_image_pixels = check_max_image_pixels(pixels)


def check_max_image_pixels(pixels) -> int:
    """The ``max_image_pixels`` option, checked (an integer >= 1)."""
    if isinstance(pixels, bool) or not isinstance(pixels, int) or pixels < 1:
        raise OptionError(
            f"invalid option `limits.max_image_pixels`: must be an integer >= 1, got {pixels!r}"
        )
    return pixels


def max_image_pixels() -> int:
    return _max_image_pixels


def check_image_size(width: int, height: int, what: str) -> None:
    """ImageTooLargeError if a ``width`` x ``height`` image is larger than the limit (checked on the
    header, before any pixel is decoded)."""
    if width < 0 or height < 0 or width * height > _max_image_pixels:
        raise ImageTooLargeError(
            f"{what} is {width} x {height} = {width * height} pixels, more than the limit of "
            f"{_max_image_pixels} ([limits] max_image_pixels)"
        )


def open_image(path_or_file, what: str):
    """A PIL image opened lazily, its size checked against the limit (decoding happens on
    ``load``). ImageError for unreadable files and decompression bombs."""
    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            im = Image.open(path_or_file)
    except FileNotFoundError:
        raise ImageError(f"image file not found: {what}") from None
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as e:
        raise ImageError(f"cannot read image {what}: {e}") from None
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as e:
        raise ImageError(f"{what}: {e}") from None
    try:
        check_image_size(*im.size, what)
    except ImageError:
        im.close()
        raise
    return im


def _decoded(im, what: str, *, lenient: bool = False):
    """Runs ``im.load()`` with PIL's own size checks off (ours ran on the header). A file cut
    short (a truncated JPEG or PNG) is an error; with ``lenient`` what it holds is decoded
    (the rest grey) and a one-line warning says so."""
    from PIL import Image, ImageFile

    old = Image.MAX_IMAGE_PIXELS
    Image.MAX_IMAGE_PIXELS = None
    try:
        im.load()
    except (OSError, SyntaxError, ValueError, MemoryError) as e:
        if not (lenient and "truncated" in str(e)):
            raise ImageError(f"cannot decode image {what}: {e}") from None
        old_truncated = ImageFile.LOAD_TRUNCATED_IMAGES
        ImageFile.LOAD_TRUNCATED_IMAGES = True
        try:
            im.load()
        except (OSError, SyntaxError, ValueError, MemoryError) as e2:
            raise ImageError(f"cannot decode image {what}: {e2}") from None
        finally:
            ImageFile.LOAD_TRUNCATED_IMAGES = old_truncated
        print(
            f"floorscan: warning: {what} is truncated ({e}): ranged as far as it decodes",
            file=sys.stderr,
        )
    finally:
        Image.MAX_IMAGE_PIXELS = old
    return im


def read_grey(path: PathLike, *, lenient: bool = False) -> np.ndarray:
    """Reads an image file (PNG, JPEG, ... 8 or 16 bit) as a (H, W) uint8 or uint16 array.
    Images larger than ``max_image_pixels`` are refused unread (ImageError). PNG files are
    decoded in Rust (:mod:`floorscan.formats.png`, the same pixels), the rest by Pillow. A
    truncated file is an ImageError, or with ``lenient`` decoded as far as it goes (a warning
    on stderr)."""
    name = os.fspath(path)
    if ("\x00" if isinstance(name, str) else b"\x00") in name:  # no file system allows one
        raise ImageError(f"cannot read image {name!r}: the path holds a NUL byte")
    try:
        with open(path, "rb") as f:
            if os.fstat(f.fileno()).st_size > max_png_file_bytes(_max_image_pixels):
                return _read_grey_pillow(path, lenient)  # the header first, the rest lazily
            data = f.read()
    except FileNotFoundError:
        raise ImageError(f"image file not found: {path}") from None
    except OSError as e:
        raise ImageError(f"cannot read image {path}: {e.strerror or e}") from None
    if not is_png(data):
        return _read_grey_pillow(path, lenient)
    try:
        return png_to_grey(data, max_pixels=_max_image_pixels)
    except ImageTooLargeError as e:
        raise ImageTooLargeError(f"{path}: {e} ([limits] max_image_pixels)") from None
    except ImageError as e:
        if lenient:
            return _read_grey_pillow(path, lenient)
        raise ImageError(f"cannot read image {path}: {e}") from None


def _read_grey_pillow(path: PathLike, lenient: bool = False) -> np.ndarray:
    """:func:`read_grey` through Pillow (every format Pillow reads)."""
    from PIL import UnidentifiedImageError

    try:
        with open_image(path, str(path)) as im:
            _decoded(im, str(path), lenient=lenient)
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
    tmp = None
    try:
        with deferred_signals():
            tmp = temp_path_for(target, ".png")
        Image.fromarray(np.ascontiguousarray(image)).save(tmp, format="PNG")
        tmp.replace(target)
    except BaseException:
        if tmp is not None:
            discard_temporary(tmp)
        raise
    return target
