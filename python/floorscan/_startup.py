"""Quiet start of the ``floorscan`` command: a Ctrl-C (or SIGTERM / SIGHUP) while the package
is still being imported, before ``floorscan.cli.main`` installs its handlers, ends the process
with one line and the signal's exit code instead of a traceback. Only active when the process
is the ``floorscan`` console script; a library import changes nothing."""

from __future__ import annotations

import os
import signal
import sys


def _is_cli() -> bool:
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    return name in ("floorscan", "floorscan.exe", "floorscan-script.py")


def _quit(signum, _frame) -> None:
    sys.stderr.write("floorscan: interrupted\n")
    raise SystemExit(128 + signum)


def install() -> None:
    if not _is_cli():
        return
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            try:
                signal.signal(getattr(signal, name), _quit)
            except (ValueError, OSError):  # not the main thread, or not allowed
                pass


install()
