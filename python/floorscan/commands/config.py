"""``floorscan config``: print the default configuration, or check a configuration file."""

from __future__ import annotations

import argparse
import sys

from ..errors import OptionError
from ..pipeline.config import Config
from ..pipeline.config_check import check_config, check_config_for_table
from ..ranging.ground_table import GroundTable


def register(sub) -> None:
    p = sub.add_parser("config", help="print the default configuration or check a config file")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--default", action="store_true", help="print the default configuration (TOML)")
    g.add_argument(
        "--check",
        metavar="CONFIG",
        help="check a configuration file as `floorscan run` does and print it in full",
    )
    p.add_argument(
        "--table",
        metavar="TABLE",
        help="with --check: also check the options that depend on the image's size "
        "(ranger.columns, ranger.start) against this ground table, as `floorscan run` does; "
        "without it they are not checked (a note says so)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    # --check builds every component `floorscan run` builds from the file, with the same
    # constructors: the two refuse exactly the same files.
    if args.default:
        if args.table:
            raise OptionError("--table goes with --check")
        sys.stdout.write(Config().to_toml())
        return 0
    cfg = Config.load(args.check)
    if args.table:
        check_config_for_table(cfg, GroundTable.load(args.table))
    else:
        check_config(cfg)
        print(
            "floorscan config: note: ranger.columns and ranger.start were not checked against "
            "an image size (give --table TABLE)",
            file=sys.stderr,
        )
    sys.stdout.write(cfg.to_toml())
    return 0
