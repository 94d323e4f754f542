"""Stopping on SIGINT (Ctrl-C), SIGTERM and SIGHUP without losing work.

- :func:`handle_signals` (the CLI's ``main``) turns SIGTERM and SIGHUP into :class:`Interrupted`
  (a ``KeyboardInterrupt``) like SIGINT, so every command stops the same way on all three.
- :class:`StopRequest` (``floorscan run``): the first signal asks the frame loop to stop after
  the current frame; a second one while frames are still being read interrupts at once.
  Once the loop has ended the outputs are written: the next signal is noted and ignored
  (every output is finished whole), the one after abandons the outputs not yet written,
  each writer removing its temporary file.

Handlers are only installed in the main thread (Python delivers signals there only).

A signal that arrives while a module is being imported (the commands import OpenCV and
matplotlib on first use) is raised once the import has finished, not inside it: an exception
raised inside a C extension's initialisation (pybind11's, for instance) leaves the extension
half set up, reports it as ``ImportError: initialization failed`` and can crash the interpreter
as it shuts down. The signal is re-checked every 20 ms through ``SIGALRM`` (the SIGALRM
handler and timer of before are put back after); a second signal while one is held stops at
once.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
import time
from typing import Dict, Iterator, Optional

STOP_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


_ABANDONED: Optional[int] = None
"""The signal that abandoned a run's unfinished outputs (see :func:`abandoned_by`)."""


def abandoned_by() -> Optional[int]:
    """The signal number that abandoned the outputs not yet written, if one did. An error a
    library raises while it is being torn down by that interruption (a writer left half-way
    asserting its state, say) is the interruption's, not a bug of its own: the command line
    reports it as interrupted."""
    return _ABANDONED


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
        held = _cancel_recheck()
        for s, h in previous.items():
            signal.signal(s, h)
    if held is not None:  # the block ended within an import's last 20 ms: hand it over
        _deliver(held, previous[held], None)


def _deliver(signum: int, handler, frame) -> None:
    """Delivers ``signum`` to ``handler`` as the interpreter would: called if a function,
    dropped if ignored, else the stop it stands for."""
    if callable(handler):
        handler(signum, frame)
    elif handler != signal.SIG_IGN:
        raise Interrupted(signum)


_IMPORT_FRAMES = ("<frozen importlib._bootstrap", "<frozen importlib._bootstrap_external")
_RECHECK_S = 0.02


def _importing(frame) -> bool:
    """Whether ``frame`` (the one a signal handler interrupted) runs inside an import."""
    while frame is not None:
        if frame.f_code.co_filename.startswith(_IMPORT_FRAMES):
            return True
        frame = frame.f_back
    return False


_PENDING: Optional[int] = None
"""A signal held until the import in progress finishes."""
_ALARM_BEFORE: Optional[tuple] = None
"""While a signal is held: the SIGALRM handler and timer it displaced, and when."""


def _raise_after_imports(signum: int, frame) -> None:
    """Raises :class:`Interrupted` now, or holds the signal until the import in progress has
    finished (:func:`_recheck`). A second signal while one is held raises at once: whoever
    sends it wants out even if an import hangs (a C extension's initialisation may then be
    left half done)."""
    global _PENDING, _ALARM_BEFORE
    if _PENDING is not None or not _importing(frame) or not hasattr(signal, "setitimer"):
        _cancel_recheck()
        raise Interrupted(signum)
    _PENDING = int(signum)
    _ALARM_BEFORE = (
        signal.signal(signal.SIGALRM, _recheck),
        signal.setitimer(signal.ITIMER_REAL, _RECHECK_S),
        time.monotonic(),
    )


def _recheck(_alarm, frame) -> None:
    """The held signal, delivered again to the handler in place now: it decides with the
    state of now (a frame loop that has ended since treats it as a signal while saving), and
    holds it again if another import is under way."""
    signum = _cancel_recheck()
    if signum is not None:
        _deliver(signum, signal.getsignal(signum), frame)


def _cancel_recheck() -> Optional[int]:
    """Stops holding: the SIGALRM handler and timer of before are put back (the timer less
    the time held); returns the signal that was held, if one was."""
    global _PENDING, _ALARM_BEFORE
    pending, before = _PENDING, _ALARM_BEFORE
    _PENDING = _ALARM_BEFORE = None
    if before is not None:
        handler, (delay_s, interval_s), since = before
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, handler if handler is not None else signal.SIG_DFL)
        if delay_s > 0:
            left = max(delay_s - (time.monotonic() - since), 1e-3)
            signal.setitimer(signal.ITIMER_REAL, left, interval_s)
    return pending


def _raise(signum, frame) -> None:
    _raise_after_imports(signum, frame)


def ignore_stop_signals() -> None:
    """Ignores SIGINT, SIGTERM and SIGHUP from now on (the command line's last act)."""
    if _in_main_thread():
        for s in STOP_SIGNALS:
            signal.signal(s, signal.SIG_IGN)


def handle_signals():
    """Context manager: SIGINT, SIGTERM and SIGHUP raise :class:`Interrupted`."""
    return _handlers(_raise)


class StopRequest:
    """Cooperative stop for a frame loop (see the module docstring). Install it once, around
    both the loop and the saving, so that no signal falls between two handlers."""

    def __init__(self) -> None:
        self.signum: Optional[int] = None
        self._in_loop = False
        self._after_loop = 0

    @property
    def requested(self) -> bool:
        return self.signum is not None

    def _on_signal(self, signum, _frame) -> None:
        if self._in_loop:
            if self.signum is not None:
                _raise_after_imports(signum, _frame)  # second signal: stop reading at once
                return
            self.signum = int(signum)
            return
        # Past the loop: the outputs are being written. Note the first signal; abandon the
        # outputs not yet written on the second (each writer removes its temporary file).
        self.signum = self.signum or int(signum)
        self._after_loop += 1
        if self._after_loop >= 2:
            global _ABANDONED
            _ABANDONED = int(signum)
            _raise_after_imports(signum, _frame)
            return
        print(
            "floorscan: saving the outputs (signal once more to abandon the rest)",
            file=sys.stderr,
        )

    def installed(self):
        """Context manager: this request handles SIGINT, SIGTERM and SIGHUP."""
        return _handlers(self._on_signal)

    @contextlib.contextmanager
    def loop(self) -> Iterator[None]:
        """Context manager for the frame loop: a first signal sets :attr:`requested`, a
        second raises :class:`Interrupted`."""
        self._in_loop = True
        try:
            yield
        finally:
            self._in_loop = False
