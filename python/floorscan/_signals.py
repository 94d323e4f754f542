"""Stopping on SIGINT (Ctrl-C), SIGTERM and SIGHUP without losing work.

- :func:`handle_signals` (the CLI's ``main``) turns SIGTERM and SIGHUP into :class:`Interrupted`
  (a ``KeyboardInterrupt``) like SIGINT, so every command stops the same way on all three.
- :class:`StopRequest` (``floorscan run``): the first signal asks the frame loop to stop after
  the current frame; a second one while frames are still being read interrupts at once.
- :func:`StopRequest.saving`: while the outputs are written, signals are noted and ignored
  (every output is finished whole); a third signal abandons the outputs not yet written,
  each writer removing its temporary file.

Handlers are only installed in the main thread (Python delivers signals there only).
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from typing import Dict, Iterator, Optional

STOP_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


class Interrupted(KeyboardInterrupt):
    """A stop signal (SIGINT, SIGTERM or SIGHUP) arrived; ``signum`` says which."""

    def __init__(self, signum: int = signal.SIGINT) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)


def exit_code(e: BaseException) -> int:
    """The shell's convention: 128 + the signal number (130 for Ctrl-C)."""
    return 128 + getattr(e, "signum", int(signal.SIGINT))


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def _handlers(handler) -> Iterator[None]:
    if not _in_main_thread():
        yield
        return
    previous: Dict[int, object] = {}
    for s in STOP_SIGNALS:
        previous[s] = signal.signal(s, handler)
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


def _raise(signum, _frame) -> None:
    raise Interrupted(signum)


def handle_signals():
    """Context manager: SIGINT, SIGTERM and SIGHUP raise :class:`Interrupted`."""
    return _handlers(_raise)


class StopRequest:
    """Cooperative stop for a frame loop (see the module docstring)."""

    def __init__(self) -> None:
        self.signum: Optional[int] = None
        self._saving = False
        self._while_saving = 0

    @property
    def requested(self) -> bool:
        return self.signum is not None

    def _on_signal(self, signum, _frame) -> None:
        if self._saving:
            self._while_saving += 1
            if self._while_saving >= 2:
                raise Interrupted(signum)
            print(
                "floorscan: still saving the outputs (signal once more to abandon the rest)",
                file=sys.stderr,
            )
            return
        if self.signum is not None:
            raise Interrupted(signum)  # second signal: stop reading at once
        self.signum = int(signum)

    def frames(self):
        """Context manager for the frame loop: a signal sets :attr:`requested`."""
        return _handlers(self._on_signal)

    @contextlib.contextmanager
    def saving(self) -> Iterator[None]:
        """Context manager for writing the outputs: signals are noted, not raised (twice)."""
        self._saving = True
        try:
            with _handlers(self._on_signal):
                yield
        finally:
            self._saving = False
