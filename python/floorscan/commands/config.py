"""``floorscan config``: print the default configuration, or check a configuration file."""

from __future__ import annotations

import argparse
import sys

from ..config import Config


def register(sub) -> None:
    p = sub.add_parser("config", help="print the default configuration or check a config file")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--default", action="store_true", help="print the default configuration (TOML)")
    g.add_argument(
        "--check", metavar="CONFIG", help="check a configuration file and print it in full"
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    cfg = Config() if args.default else Config.load(args.check)
    sys.stdout.write(cfg.to_toml())
    return 0
