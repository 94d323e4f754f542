"""The ``floorscan`` command line. Each subcommand lives in ``floorscan/commands/<name>.py``."""

from __future__ import annotations

import argparse
import importlib
import sys
from typing import List, Optional

from .errors import FloorscanError


def build_parser() -> argparse.ArgumentParser:
    from . import __version__
    from .commands import COMMAND_MODULES

    parser = argparse.ArgumentParser(
        prog="floorscan", description="One camera as a range sensor, fused into occupancy maps."
    )
    parser.add_argument("--version", action="version", version=f"floorscan {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: Optional[List[str]] = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "run", None):
        parser.print_help()
        return 2
    try:
        return int(args.run(args) or 0)
    except FloorscanError as e:
        print(f"floorscan {args.command}: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"floorscan {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
