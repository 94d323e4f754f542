"""A minimal progress line on stderr (no dependency): frames done, rate, skips."""

from __future__ import annotations

import sys
import time
from typing import Optional, TextIO


class Progress:
    def __init__(
        self, total: Optional[int], *, enabled: bool = True, stream: Optional[TextIO] = None
    ) -> None:
        # The stream is looked up when the line is made, not when this module is imported
        # (sys.stderr may have been replaced, and the old one closed, since).
        stream = stream if stream is not None else sys.stderr
        self.total = total or None
        try:
            self.enabled = enabled and stream.isatty()
        except (ValueError, OSError):  # a closed or detached stream: no progress line
            self.enabled = False
        self.stream = stream
        self.start = time.perf_counter()
        self._last = 0.0

    def update(self, done: int, *, skipped: int = 0, dropped: int = 0) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last < 0.2 and (self.total is None or done < self.total):
            return
        self._last = now
        rate = done / max(now - self.start, 1e-9)
        head = f"{done}/{self.total}" if self.total else f"{done}"
        extra = (f", {skipped} skipped" if skipped else "") + (
            f", {dropped} dropped" if dropped else ""
        )
        self.stream.write(f"\r  frames {head} ({rate:.0f}/s{extra})   ")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
