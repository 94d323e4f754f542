"""``floorscan fleet``: many recordings (several robots, several days) mapped in parallel on Ray
(or one after the other in this process) and merged into one map (docs/fleet.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..commands._output import FOLDER, add_output
from ..errors import OptionError
from .jobs import map_fleet
from .spec import parse_recording, read_fleet_toml


def register(sub) -> None:
    p = sub.add_parser(
        "fleet",
        help="map many recordings on Ray (or serially) and merge them into one map",
        description="Maps each recording as `floorscan run` does into DIR/<name>/, then merges "
        "the recordings that share a map frame into DIR/merged/.",
    )
    p.add_argument(
        "recordings",
        nargs="*",
        metavar="REC",
        help="recording (what `floorscan run` accepts), or REC::TABLE for its own calibration",
    )
    p.add_argument("--fleet", metavar="TOML", help="fleet file listing recordings and their tables")
    add_output(p, FOLDER, "output folder DIR")
    p.add_argument(
        "--ray",
        nargs="?",
        const="local",
        metavar="ADDRESS",
        help="run on Ray: `local` (also --ray alone) starts it here, an address joins a "
        "cluster; without --ray: map in this process, one after the other",
    )
    p.add_argument("--workers", type=int, help="CPUs of a --ray local instance (default: all)")
    p.add_argument("--table", help="ground table for recordings that give none")
    p.add_argument("--config", help="configuration TOML for recordings that give none")
    p.add_argument(
        "--shared-frame",
        action="store_true",
        help="all recordings are in one map frame (default: only those with the same start pose)",
    )
    p.add_argument(
        "--max-retries",
        type=int,
        default=3,
        help="re-runs of a recording whose worker died (default %(default)s)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    recs = [parse_recording(t) for t in args.recordings]
    if args.fleet:
        recs += read_fleet_toml(args.fleet)
    if not recs:
        raise OptionError("give recordings (REC or REC::TABLE) or --fleet FILE.toml")
    result = map_fleet(
        recs,
        args.output,
        ray=args.ray,
        table=args.table,
        config=args.config,
        shared_frame=args.shared_frame,
        max_retries=args.max_retries,
        workers=args.workers,
    )
    for r in result.recordings:
        extra = f"{r.get('frames_mapped')} frames" if r["status"] == "ok" else r.get("error", "")
        print(f"  {r['name']}: {r['status']} {extra}")
    groups = result.groups
    if len(groups) > 1 and result.merged:
        print(
            f"{len(groups)} map frames (start poses differ; --shared-frame if they are one): "
            + "; ".join(", ".join(g) for g in groups),
            file=sys.stderr,
        )
    if result.merge_error:
        print(f"floorscan fleet: merge failed: {result.merge_error}", file=sys.stderr)
    ok = len(result.recordings) - len(result.failed)
    print(
        f"{ok}/{len(result.recordings)} recordings mapped in {result.wall_s:.1f} s ({result.mode})"
        + f" -> {args.output}/"
    )
    out = Path(args.output)
    for folder in result.merged:
        print(f"merged map: {out / folder / 'map.yaml'}")
    if result.interrupted:
        return 130
    return 1 if result.failed or result.merge_error else 0
