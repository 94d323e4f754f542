"""Quiet start of the ``floorscan`` command: a Ctrl-C (or SIGTERM / SIGHUP) while the package
is still being imported, before ``floorscan.cli.main`` installs its handlers, ends the process
with one line and the signal's exit code instead of a traceback. Only active when the process
is the ``floorscan`` console script; a library import changes nothing."""

from __future__ import annotations

# `_signal` (the interpreter's built-in C module) rather than `signal`, which imports enum and
# functools first: the handlers are in place a few milliseconds sooner.
import _signal
import os
import sys


def _is_cli() -> bool:
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    return name in ("floorscan", "floorscan.exe", "floorscan-script.py")


def _quit(signum, _frame) -> None:
    # Nothing has been written yet while the package imports: end at once. (Raising here
    # would surface inside whatever module is importing, e.g. as numpy's ImportError.)
    try:
        sys.stderr.write("floorscan: interrupted\n")
        sys.stderr.flush()
    finally:
        os._exit(128 + signum)


def install() -> None:
    if not _is_cli():
        return
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(_signal, name):
            try:
                _signal.signal(getattr(_signal, name), _quit)
            except (ValueError, OSError):  # not the main thread, or not allowed
                pass


install()
