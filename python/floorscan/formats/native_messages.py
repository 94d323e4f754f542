"""What native decoders print: OpenCV's video readers (its own AVI parser, FFmpeg) write their
complaints about a damaged file straight to the process's stderr (file descriptor 2), where
Python cannot catch them and a user sees lines such as ``[mjpeg @ 0x55..] huffman table decode
error`` before floorscan's own one-line error. :func:`native_messages` catches them for the
duration of a call, so the caller can turn them into its own message (a frame skipped for a
decoder error, an error that names the file) instead.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from typing import Iterator, List

MAX_MESSAGE_BYTES = 64 << 10
"""At most this much of what was printed is kept (a decoder may print a line per macroblock)."""


class NativeMessages:
    """The lines native code printed on stderr inside :func:`native_messages`."""

    def __init__(self) -> None:
        self.lines: List[str] = []

    @property
    def first(self) -> str:
        """The first line (empty when nothing was printed)."""
        return self.lines[0] if self.lines else ""

    def __bool__(self) -> bool:
        return bool(self.lines)


@contextlib.contextmanager
def native_messages() -> Iterator[NativeMessages]:
    """Redirects file descriptor 2 to a temporary file while the block runs and gives back the
    lines written there (Python's own ``sys.stderr`` is flushed first, so nothing of ours is
    caught). Where stderr cannot be redirected (no descriptor 2), the block just runs."""
    caught = NativeMessages()
    try:
        saved = os.dup(2)
    except OSError:
        yield caught
        return
    try:
        sys.stderr.flush()
    except (AttributeError, ValueError, OSError):
        pass
    with tempfile.TemporaryFile() as sink:
        os.dup2(sink.fileno(), 2)
        try:
            yield caught
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            text = sink.read(MAX_MESSAGE_BYTES).decode("utf-8", "replace")
            caught.lines = [line.strip() for line in text.splitlines() if line.strip()]
