"""The progress line of ``floorscan run`` on stderr (tqdm): frames done, rate, skipped and
dropped frames. Shown on a terminal only."""

from __future__ import annotations

import sys
from typing import Optional, TextIO

from tqdm import tqdm


class Progress:
    """``update(done, skipped=, dropped=)`` after each frame, ``close()`` at the end."""

    def __init__(
        self, total: Optional[int], *, enabled: bool = True, stream: Optional[TextIO] = None
    ) -> None:
        # The stream is looked up when the bar is made, not when this module is imported
        # (sys.stderr may have been replaced, and the old one closed, since).
        stream = stream if stream is not None else sys.stderr
        try:
            enabled = enabled and stream.isatty()
        except (ValueError, OSError):  # a closed or detached stream: no progress line
            enabled = False
        self.bar = tqdm(
            total=total or None,
            file=stream,
            unit="frame",
            desc="  frames",
            disable=not enabled,
            mininterval=0.2,
            leave=True,
        )

    def update(self, done: int, *, skipped: int = 0, dropped: int = 0) -> None:
        if self.bar.disable:
            return
        extra = {}
        if skipped:
            extra["skipped"] = skipped
        if dropped:
            extra["dropped"] = dropped
        if extra:
            self.bar.set_postfix(extra, refresh=False)
        self.bar.update(done - self.bar.n)

    def close(self) -> None:
        self.bar.close()
