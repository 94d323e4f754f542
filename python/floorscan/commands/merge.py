"""``floorscan merge``: maps already made (by ``floorscan run`` or ``floorscan fleet``) summed
exactly from their stored evidence into one map."""

from __future__ import annotations

import argparse

from ..mapping.merge import cell_counts, merge_maps
from ._output import FOLDER, add_output


def register(sub) -> None:
    p = sub.add_parser(
        "merge",
        help="merge maps made before into one map (from their stored evidence)",
        description="Sums the unclamped evidence (map.evidence.npz) of maps on one cell "
        "lattice and writes the merged map_server map, PNG, evidence and summary.json.",
    )
    p.add_argument(
        "maps", nargs="+", metavar="MAP", help="map YAML, its .evidence.npz, or a run output folder"
    )
    add_output(p, FOLDER, "output folder")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    merged = merge_maps(args.maps, args.output)
    c = cell_counts(merged)
    h, w = merged.values.shape
    print(
        f"merged {len(args.maps)} maps: {w} x {h} cells, {c['known']} known "
        f"({c['free']} free, {c['occupied']} occupied) -> {args.output}/map.yaml"
    )
    return 0
