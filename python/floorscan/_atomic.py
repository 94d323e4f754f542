"""Atomic file writes: write a temporary file beside the target, then rename it over the target,
so a crash never leaves a half-written file where a good one was."""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import threading
from pathlib import Path
from typing import Callable, Iterator, Union

from .errors import OutputError

PathLike = Union[str, "os.PathLike[str]"]


def write_atomic(path: PathLike, data: Union[bytes, str]) -> Path:
    """Writes ``data`` to ``path`` atomically; returns the path."""
    payload = data.encode("utf-8") if isinstance(data, str) else data
    return write_atomic_with(path, lambda f: f.write(payload))


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _make_readable(path: Union[str, Path]) -> None:
    """mkstemp creates files readable by their owner only; give them the permissions an
    ordinary ``open(path, "w")`` would (a map_server running as another user must read maps)."""
    os.chmod(path, 0o666 & ~_umask())


def output_error(path: PathLike, e: OSError) -> OutputError:
    """The one-line error for an output that cannot be written (a folder, read-only, under a
    file, a name too long, a full disk)."""
    target = Path(path)
    why = e.strerror or str(e)
    if target.is_dir():
        why = "it is a folder"
    elif any(p.exists() and not p.is_dir() for p in target.parents):
        why = "a parent of it is a file"
    return OutputError(f"cannot write {target}: {why}")


def _prepare(target: Path) -> None:
    if target.is_dir():
        raise OutputError(f"cannot write {target}: it is a folder")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise output_error(target, e) from None


@contextlib.contextmanager
def deferred_signals() -> Iterator[None]:
    """Holds SIGINT, SIGTERM, SIGHUP (and SIGALRM) back (they are delivered when the block ends), so that
    creating a temporary file and recording its name happen together: a signal can then never
    leave a temporary file that no cleanup knows about. Both kinds of pending signal are held:
    those the kernel has not delivered yet (masked) and those it has, whose Python handler
    would otherwise run at any bytecode inside the block (a recording handler stands in for
    the block's length). Main thread only; elsewhere a no-op."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(
        signal, "pthread_sigmask"
    ):
        yield
        return
    # SIGALRM too: it carries a stop signal held back until an import had finished (_signals)
    names = ("SIGINT", "SIGTERM", "SIGHUP", "SIGALRM")
    held = [getattr(signal, n) for n in names if hasattr(signal, n)]
    previous_mask = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    handlers = {s: signal.getsignal(s) for s in held}
    caught: list = []
    try:
        for s in held:
            signal.signal(s, lambda signum, _frame: caught.append(signum))
        yield
    finally:
        for s, h in handlers.items():
            signal.signal(s, h if h is not None else signal.SIG_DFL)
        signal.pthread_sigmask(signal.SIG_SETMASK, previous_mask)
        for signum in caught:  # delivered now, to the handlers of before the block
            h = handlers[signum]
            if callable(h):
                h(signum, None)
            elif h != signal.SIG_IGN:
                signal.raise_signal(signum)


def write_atomic_with(path: PathLike, write: Callable[[object], object], suffix: str = "") -> Path:
    """Calls ``write(binary_file)`` on a temporary file, then renames it to ``path``. An
    output that cannot be written raises OutputError (also an OSError); nothing is left
    behind."""
    target = Path(path)
    _prepare(target)
    tmp = None
    try:
        # created and named with signals held: a signal held back is delivered as the block
        # ends, inside this try, so the temporary file goes with it
        with deferred_signals():
            fd, tmp = tempfile.mkstemp(
                prefix=f".{target.name[:200]}.", suffix=suffix or ".tmp", dir=target.parent
            )
            f = os.fdopen(fd, "wb")
        with f:
            _make_readable(tmp)
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, target)
    except BaseException as e:
        if tmp is not None:
            discard_temporary(tmp)
        if isinstance(e, OSError) and not isinstance(e, OutputError):
            raise output_error(target, e) from None
        raise
    return target


def discard_temporary(tmp: PathLike) -> None:
    """Removes a temporary file (if there) with signals held back, so that a further signal of
    a burst cannot interrupt the clean-up and leave it behind."""
    with deferred_signals():
        Path(tmp).unlink(missing_ok=True)


def temp_path_for(path: PathLike, suffix: str) -> Path:
    """A fresh temporary path beside ``path`` (for writers that insist on a file name, such as
    image encoders choosing a format by extension). Rename it with ``os.replace`` when done.
    Call it inside ``with deferred_signals():`` and assign the result there, so a signal cannot
    fall between the file's creation and the caller knowing its name."""
    target = Path(path)
    _prepare(target)
    try:
        fd, tmp = tempfile.mkstemp(
            prefix=f".{target.name[:200]}.", suffix=suffix, dir=target.parent
        )
    except OSError as e:
        raise output_error(target, e) from None
    os.close(fd)
    _make_readable(tmp)
    return Path(tmp)
