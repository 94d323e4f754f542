"""PNG files decoded in Rust (crates/floorscan-codec, the GIL released while decoding): the
same pixels as Pillow, about five times faster here (BENCHMARKS.md), with the decoded size
bounded on the header.

Pillow stays the reader of every other format (:func:`floorscan.formats.image_io.read_grey`
uses these functions for PNG files and Pillow for the rest).

>>> import numpy as np, io
>>> from PIL import Image
>>> buf = io.BytesIO(); Image.fromarray(np.arange(12, dtype=np.uint8).reshape(3, 4)).save(buf, "PNG")
>>> png_to_grey(buf.getvalue(), max_pixels=100)
array([[ 0,  1,  2,  3],
       [ 4,  5,  6,  7],
       [ 8,  9, 10, 11]], dtype=uint8)
"""

from __future__ import annotations

import numpy as np

from .._native import formats as _native

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
"""The eight bytes every PNG file starts with."""


def is_png(data: bytes) -> bool:
    """Whether ``data`` starts with the PNG signature."""
    return data[:8] == PNG_SIGNATURE


def max_png_file_bytes(max_pixels: int) -> int:
    """Most bytes a PNG file of ``max_pixels`` pixels is read into memory for: its samples
    stored uncompressed twice over plus 64 MiB of other chunks (larger files are left to
    Pillow, which reads lazily and refuses an oversized header first)."""
    return _native.max_png_file_bytes(int(max_pixels))


def png_to_grey(data: bytes, *, max_pixels: int) -> np.ndarray:
    """PNG file bytes to a (H, W) grey image: uint8, or uint16 for 16-bit grey files. Colour
    becomes ITU-R BT.601 luma exactly as Pillow's ``convert("L")`` computes it, alpha is
    dropped, palettes and 1/2/4-bit grey are expanded. ImageError (one line) for bytes that are
    not a valid PNG and for a header declaring more than ``max_pixels`` (width x height),
    refused before any pixel is decoded."""
    return _native.png_to_grey(data, int(max_pixels))


def png_to_array(data: bytes, *, max_pixels: int) -> np.ndarray:
    """PNG file bytes to pixels as stored: (H, W) grey, (H, W, 2) grey + alpha, (H, W, 3) RGB or
    (H, W, 4) RGBA; uint16 for 16-bit grey, uint8 otherwise (palettes expanded to RGB or RGBA,
    other 16-bit types to their high byte: Pillow's modes for the same file). Errors as
    :func:`png_to_grey`."""
    return _native.png_to_array(data, int(max_pixels))
