"""
Formats: image files decoded in Rust (PNG), the GIL released while decoding.
"""

from _typeshed import Incomplete
from typing import Any, SupportsIndex

def png_to_array(data: bytes, max_pixels: SupportsIndex) -> Any:
    """
    PNG file bytes to pixels: uint8, or uint16 for 16-bit grey; (H, W) grey, (H, W, 2) grey +
    alpha, (H, W, 3) RGB or (H, W, 4) RGBA (palettes expanded, other 16-bit types to their
    high byte, as Pillow reads them). `max_pixels` bounds width x height, checked on the header.
    """

def png_to_grey(data: bytes, max_pixels: SupportsIndex) -> Any:
    """
    PNG file bytes to one grey channel (H, W): uint8, or uint16 for 16-bit grey files; colour
    becomes BT.601 luma exactly as Pillow's `convert("L")`, alpha is dropped. `max_pixels`
    bounds width x height, checked on the header.
    """

def __getattr__(name: str) -> Incomplete: ...
