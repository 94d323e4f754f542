"""The ``floorscan`` command line. Each subcommand lives in ``floorscan/commands/<name>.py``.

Every failure ends as one line on stderr (``floorscan COMMAND: error: ...``) and an exit code
(docs/limits.md); ``--debug`` shows the traceback instead.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from typing import List, Optional

from . import __version__
from ._signals import abandoned_by, exit_code, handle_signals, ignore_stop_signals
from .commands import COMMAND_MODULES
from .commands._output import refuse_overwrites
from .errors import FloorscanError

EXIT_OK = 0
EXIT_ERROR = 1
"""Bad input or options (a FloorscanError): the message says what to fix."""
EXIT_USAGE = 2
"""Bad command line (argparse)."""
EXIT_OS_ERROR = 3
"""The operating system refused a read or write (permissions, disk full, path too long)."""
EXIT_OUT_OF_MEMORY = 4
"""Memory ran out (raise nothing: lower a limit, see docs/limits.md)."""
EXIT_INTERNAL = 5
"""A bug in floorscan (please report it with the ``--debug`` traceback)."""
# 128 + N: stopped by signal N (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP), outputs saved.


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="floorscan", description="One camera as a range sensor, fused into occupancy maps."
    )
    parser.add_argument("--version", action="version", version=f"floorscan {__version__}")
    parser.add_argument(
        "--debug", action="store_true", help="show the traceback of an error (for bug reports)"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def _one_line(e: BaseException) -> str:
    text = " ".join(str(e).split()) or type(e).__name__
    return text if len(text) <= 600 else text[:597] + "..."


def _os_error(e: OSError) -> str:
    where = f": {e.filename}" if getattr(e, "filename", None) else ""
    return f"{e.strerror or e}{where}"


def main(argv: Optional[List[str]] = None) -> int:
    try:
        return _main(argv)
    finally:
        if argv is None:
            # The console script is about to exit with its outputs complete: a late signal
            # must not kill it with another status during the interpreter's shutdown.
            ignore_stop_signals()


def _main(argv: Optional[List[str]]) -> int:
    command = "floorscan"
    debug = "--debug" in (sys.argv[1:] if argv is None else argv)
    try:
        with handle_signals():
            parser = build_parser()
            args = parser.parse_args(argv)
            debug = args.debug
            command = f"floorscan {args.command}" if args.command else "floorscan"
            if not getattr(args, "run", None):
                parser.print_help()
                return EXIT_USAGE
            refuse_overwrites(args)  # before any work: nothing overwritten without --force
            return int(args.run(args) or 0)
    except SystemExit:
        raise
    except KeyboardInterrupt as e:
        if debug:
            raise
        print(f"{command}: interrupted", file=sys.stderr)
        return exit_code(e)
    except FloorscanError as e:
        if debug:
            raise
        print(f"{command}: error: {_one_line(e)}", file=sys.stderr)
        return EXIT_OS_ERROR if isinstance(e, OSError) else EXIT_ERROR
    except MemoryError:
        if debug:
            raise
        print(f"{command}: error: out of memory (see docs/limits.md)", file=sys.stderr)
        return EXIT_OUT_OF_MEMORY
    except OSError as e:
        if debug:
            raise
        print(f"{command}: error: {_one_line(Exception(_os_error(e)))}", file=sys.stderr)
        return EXIT_OS_ERROR
    except Exception as e:
        if debug:
            raise
        signum = abandoned_by()
        if signum is not None:
            print(f"{command}: interrupted (unfinished outputs abandoned)", file=sys.stderr)
            return 128 + signum
        print(
            f"{command}: internal error ({type(e).__name__}: {_one_line(e)}); "
            "please report it with the output of --debug",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
