"""Animated GIFs written frame by frame by a Rust thread (crates/floorscan-codec, ``gif``): the
caller draws each frame in indices of one shared palette (no per-frame colour quantisation) and
hands it over; LZW encoding and writing run beside the caller, without the GIL. The file
appears at its path only when :meth:`GifWriter.close` has written all of it (atomic rename).

>>> import numpy as np, tempfile, pathlib
>>> from PIL import Image
>>> palette = np.array([[0, 0, 0], [255, 0, 0]], dtype=np.uint8)
>>> path = pathlib.Path(tempfile.mkdtemp()) / "a.gif"
>>> gif = GifWriter(path, width=3, height=2, palette=palette, frame_s=0.1)
>>> gif.add(np.array([[0, 1, 0], [1, 0, 1]], dtype=np.uint8))
>>> gif.close() == path
True
>>> with Image.open(path) as im:
...     np.asarray(im).tolist()
[[0, 1, 0], [1, 0, 1]]
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

import numpy as np

from .._atomic import PathLike, deferred_signals, temp_path_for
from .._native import formats as _native
from ..errors import ImageError


class GifWriter:
    """A looping animation of ``width`` x ``height`` frames sharing ``palette`` ((N, 3) uint8
    RGB, N <= 256), each shown ``frame_s`` seconds (GIF counts in 1/100 s). Written to a
    temporary file beside ``path``; :meth:`close` renames it into place, :meth:`abort` removes
    it. OutputError when the file cannot be written."""

    def __init__(
        self, path: PathLike, *, width: int, height: int, palette: np.ndarray, frame_s: float
    ) -> None:
        self.path = Path(path)
        pal = np.ascontiguousarray(palette, dtype=np.uint8)
        if pal.ndim != 2 or pal.shape[1] != 3:
            raise ImageError(f"palette must be (N, 3) uint8 RGB, got shape {pal.shape}")
        self.shape = (int(height), int(width))
        self._tmp: Optional[Path] = None
        # A signal held back here is delivered as the block ends, still inside the try: the
        # temporary file goes with the failed constructor. A caller whose signals raise holds
        # them around ``writer = GifWriter(...)`` too, so the writer cannot be lost between
        # this constructor returning and the assignment.
        try:
            with deferred_signals():
                self._tmp = temp_path_for(self.path, ".gif")
                delay_cs = min(max(round(frame_s * 100), 0), 65535)
                self._native = _native.GifStream(
                    str(self._tmp), int(width), int(height), pal.tobytes(), delay_cs
                )
        except BaseException:
            self._remove_temporary()
            raise

    def add(self, indices: np.ndarray) -> None:
        """Appends a (height, width) uint8 frame of palette indices (blocks while the encoder
        thread is 32 frames behind)."""
        if not (
            isinstance(indices, np.ndarray)
            and indices.dtype == np.uint8
            and indices.shape == self.shape
        ):
            got = getattr(indices, "shape", type(indices).__name__)
            raise ImageError(f"GIF frame must be {self.shape} (H, W) uint8 indices, got {got}")
        self._native.push(indices)

    def close(self) -> Path:
        """Finishes the file (every frame encoded, synced) and renames it into place."""
        try:
            self._native.finish()
            os.replace(self._tmp, self.path)
        except BaseException:
            self.abort()
            raise
        self._tmp = None
        return self.path

    def abort(self) -> None:
        """Stops the encoder and removes the temporary file (idempotent). A signal meanwhile
        is delivered once the file is gone."""
        with deferred_signals():
            try:
                self._native.abort()
            finally:
                self._remove_temporary()

    def _remove_temporary(self) -> None:
        if self._tmp is not None:
            self._tmp.unlink(missing_ok=True)
            self._tmp = None
