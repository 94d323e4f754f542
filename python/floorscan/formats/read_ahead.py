"""A dataset's image files read and decoded ahead of the frame loop: PNG files by Rust threads
(crates/floorscan-codec ``read_ahead``: no GIL and no Python per frame on their side), in file
order, with a bounded number of decoded frames waiting; any file they leave (another format,
unreadable, damaged, over ``[limits] max_image_pixels``) is read in its turn by
:func:`~floorscan.formats.image_io.read_grey`, whose pixels and errors are the reference.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterator, Sequence, Union

import numpy as np

from .._native import formats as _native
from ..errors import FloorscanError
from .image_io import max_image_pixels, read_grey

READ_AHEAD_FRAMES = 8
"""Decoded frames waiting for the frame loop at most (bounded memory: 8 frames, 2.4 MB at
640 x 480)."""


def decode_threads() -> int:
    """Decoding threads: one per core beyond the frame loop's, two to four. Two even on two
    cores: the threads sleep once they are ``depth`` frames ahead, so the second costs no CPU,
    and it keeps decoding while the first is descheduled (on this 2-core machine the frame
    loop waited less for its images with two threads than with one)."""
    return max(2, min(4, (os.cpu_count() or 2) - 1))


def read_grey_ahead(
    paths: Sequence[Path], *, depth: int = READ_AHEAD_FRAMES, threads: int = 0
) -> Iterator[Union[np.ndarray, FloorscanError]]:
    """Each file's (H, W) uint8/uint16 grey image in order (:func:`read_grey`'s pixels), or the
    error :func:`read_grey` raises for it (returned, not raised, so the caller can count it).
    ``threads`` = 0: :func:`decode_threads`. Closing the iterator stops the threads."""
    ahead = _native.PngReadAhead(
        [str(p) for p in paths], max_image_pixels(), max(depth, 1), threads or decode_threads()
    )
    try:
        for path, image in zip(paths, ahead):
            if image is None:
                try:
                    image = read_grey(path)
                except FloorscanError as e:
                    yield e
                    continue
            yield image
    finally:
        ahead.close()
