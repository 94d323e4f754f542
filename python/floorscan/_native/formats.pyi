"""
Formats: image files in Rust, the GIL released: PNG decoding (and reading ahead), the
overlay's GIF stream.
"""

from _typeshed import Incomplete, SupportsGetItem
from os import PathLike
from typing import Any, SupportsIndex, final

@final
class GifStream:
    """
    An animated GIF being written to `path` (created or truncated) by a background thread: a
    `width` x `height` animation with one global `palette` (bytes r, g, b, ... of 1 to 256
    colours), each frame shown for `delay_cs` centiseconds, looping forever. The file is
    complete (trailer written, synced) when `finish` returns.
    """
    def __new__(cls, /, path: str | PathLike[str], width: SupportsIndex, height: SupportsIndex, palette: bytes, delay_cs: SupportsIndex) -> GifStream: ...
    def abort(self, /) -> None:
        """
        Stops the encoder and closes the file, whatever it holds (the caller removes it).
        """
    def finish(self, /) -> None:
        """
        Waits for every queued frame, writes the trailer and syncs the file.
        """
    def push(self, /, indices: Incomplete) -> None:
        """
        Queues one (height, width) uint8 frame of palette indices (blocks while the encoder is
        32 frames behind).
        """

@final
class PngReadAhead:
    """
    Grey images of PNG `paths`, in order, decoded ahead by `threads` Rust threads with at most
    `depth` decoded frames waiting. Iterating gives each file's (H, W) uint8/uint16 image, or
    None for a file it did not decode (not a PNG, unreadable, damaged, over `max_pixels`): read
    that one with the general reader, which reports the error.
    """
    def __iter__(self, /) -> PngReadAhead: ...
    def __new__(cls, /, paths: SupportsGetItem[int, str | PathLike[str]], max_pixels: SupportsIndex, depth: SupportsIndex, threads: SupportsIndex) -> PngReadAhead: ...
    def __next__(self, /) -> Any: ...
    def close(self, /) -> None:
        """
        Stops the decoding threads (and waits for them); iterating then ends.
        """

def max_png_file_bytes(max_pixels: SupportsIndex) -> int:
    """
    Most bytes a PNG file of `max_pixels` pixels is read into memory for (larger files go to
    Pillow, which reads lazily and checks the header first).
    """

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
