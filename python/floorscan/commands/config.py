"""``floorscan config``: print the default configuration, or check a configuration file."""

from __future__ import annotations

import argparse
import sys

from ..pipeline.config import Config
from ..pipeline.config_check import check_config


def register(sub) -> None:
    p = sub.add_parser("config", help="print the default configuration or check a config file")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--default", action="store_true", help="print the default configuration (TOML)")
    g.add_argument(
        "--check",
        metavar="CONFIG",
        help="check a configuration file as `floorscan run` does and print it in full",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    # --check builds every component `floorscan run` builds from the file, with the same
    # constructors: the two refuse exactly the same files.
    cfg = Config() if args.default else check_config(Config.load(args.check))
    sys.stdout.write(cfg.to_toml())
    return 0
