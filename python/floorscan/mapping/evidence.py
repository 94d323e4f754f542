"""Unclamped evidence maps: the order-free record of what a recording saw, and the exact merge
of several of them (several robots, several days) into one map.

A global map keeps, beside its clamped log-odds, the plain sum of every increment each cell
received (int32, 1/1000 nat; see ``crates/floorscan-core/src/mapping/evidence.rs``). ``floorscan run``
saves it as ``map.evidence.npz`` beside ``map.yaml`` (format in docs/formats.md). Summing
evidence is exact and commutative: ``merge([a, b]) == merge([b, a]) == a + b`` cell for cell,
and equal to the evidence of one grid fed both recordings. The merged occupancy map clamps the
sum once (:meth:`EvidenceMap.to_grid`); a sequential run clamps after every scan instead, which
favours recent observations (see docs/fleet.md, "What clamping changes").
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from .._atomic import PathLike, deferred_signals, write_atomic_with
from .._native import mapping as _native
from ..errors import FileFormatError, OptionError, UnsupportedVersionError
from ..options import check, defaults
from .log_odds import UNITS_PER_NAT

FORMAT = "floorscan-evidence"
VERSION = 1
EVIDENCE_SUFFIX = ".evidence.npz"
MAX_CELLS = 1 << 28
"""Largest evidence array read or built (1 GiB of int32)."""

_OPTION_NAMES = ("clamp_min_nats", "clamp_max_nats", "occupied_threshold", "free_threshold")


def evidence_path(map_yaml: PathLike) -> Path:
    """Where a map_server map's evidence lives: ``map.yaml`` -> ``map.evidence.npz``."""
    p = Path(map_yaml)
    return p.with_name(p.stem + EVIDENCE_SUFFIX)


def _grid_default(key: str) -> float:
    """A default of the core's ``GridOptions`` (the grid options have one home: Rust)."""
    return defaults("grid")[key]


@dataclass(frozen=True)
class EvidenceMap:
    """Summed log-odds increments on a world-placed rectangle of cells.

    ``values[row, col]`` [1/1000 nat] is the cell whose lower-left corner is ``origin_m +
    cell_size_m * (col, row)`` (row 0 the lowest y, as ``nav_msgs/OccupancyGrid``). The grid
    options say how to turn it back into an occupancy map; ``recordings`` names what was summed;
    ``ray_walk`` is the grid's ray walk the free evidence followed (``GridOptions.ray_walk``:
    which cells a ray clears), None where unknown (files written before it was recorded).
    """

    values: np.ndarray
    cell_size_m: float
    origin_m: Tuple[float, float]
    clamp_min_nats: float = field(default_factory=lambda: _grid_default("clamp_min_nats"))
    clamp_max_nats: float = field(default_factory=lambda: _grid_default("clamp_max_nats"))
    occupied_threshold: float = field(default_factory=lambda: _grid_default("occupied_threshold"))
    free_threshold: float = field(default_factory=lambda: _grid_default("free_threshold"))
    recordings: Tuple[str, ...] = field(default=())
    ray_walk: Optional[str] = None

    def __post_init__(self) -> None:
        if self.ray_walk is not None:
            if not isinstance(self.ray_walk, str):
                raise OptionError(
                    f"invalid option `ray_walk`: must be a string or None, got {self.ray_walk!r}"
                )
            check("grid", {"ray_walk": self.ray_walk})  # the core's own list of walks

    @classmethod
    def from_grid(cls, grid, *, name: str = "") -> EvidenceMap:
        """The evidence layer of an :class:`~floorscan.OccupancyGrid` made with
        ``keep_evidence=True`` (empty array if nothing was observed)."""
        if not grid._native.keeps_evidence:
            raise OptionError("this grid does not keep evidence: build it with keep_evidence=True")
        go = grid.options["grid"]
        s = float(go["cell_size_m"])
        o = go["origin_m"]
        ext = grid._native.evidence_extent()
        if ext is None:
            values, origin = np.zeros((0, 0), dtype=np.int32), (float(o["x"]), float(o["y"]))
        else:
            x, y, w, h = ext
            values = grid._native.evidence_values(x, y, w, h)
            origin = (float(o["x"]) + s * x, float(o["y"]) + s * y)
        return cls(
            values=values,
            cell_size_m=s,
            origin_m=origin,
            recordings=(name,) if name else (),
            ray_walk=str(go["ray_walk"]),
            **{k: float(go[k]) for k in _OPTION_NAMES},
        )

    @property
    def options(self) -> Dict[str, float]:
        return {k: getattr(self, k) for k in _OPTION_NAMES}

    def clamped(self) -> np.ndarray:
        """The occupancy log-odds of the map this evidence makes: each sum clamped once to the
        options' bounds, int16 [1/1000 nat]."""
        lo = round(self.clamp_min_nats * UNITS_PER_NAT)
        hi = round(self.clamp_max_nats * UNITS_PER_NAT)
        return np.clip(self.values, lo, hi).astype(np.int16)

    # --- files ------------------------------------------------------------------------
    def save(self, path: PathLike) -> Path:
        """Writes the documented ``.evidence.npz`` file atomically."""
        arrays = {
            "format": np.array(FORMAT),
            "version": np.array(VERSION, dtype=np.int64),
            "evidence": np.ascontiguousarray(self.values, dtype=np.int32),
            "cell_size_m": np.array(self.cell_size_m, dtype=np.float64),
            "origin_m": np.array(self.origin_m, dtype=np.float64),
            "recordings": np.array(list(self.recordings), dtype=str).reshape(-1),
            **{k: np.array(v, dtype=np.float64) for k, v in self.options.items()},
        }
        if self.ray_walk is not None:
            arrays["ray_walk"] = np.array(self.ray_walk)
        return write_atomic_with(path, lambda f: _savez_whole(f, arrays))

    @classmethod
    def load(cls, path: PathLike) -> EvidenceMap:
        """Reads an ``.evidence.npz`` file, checked (kind, version, dtypes, size bound)."""
        path = Path(path)
        try:
            with zipfile.ZipFile(path) as z:
                big = [i.filename for i in z.infolist() if i.file_size > 4 * MAX_CELLS + 4096]
            if big:
                raise FileFormatError(f"{path}: {big[0]} is larger than {MAX_CELLS} cells")
            with np.load(path, allow_pickle=False) as npz:
                d = {k: npz[k] for k in npz.files}
        except (OSError, ValueError, zipfile.BadZipFile) as e:
            raise FileFormatError(f"cannot read evidence file {path}: {e}") from None
        if "format" not in d or str(d["format"]) != FORMAT:
            raise FileFormatError(f"{path}: not a floorscan evidence file")
        version = int(d.get("version", -1))
        if version != VERSION:
            raise UnsupportedVersionError(
                f"{path}: evidence file version {version} (this build reads version {VERSION})"
            )
        try:
            values = d["evidence"]
            scalars = {k: float(d[k]) for k in ("cell_size_m",) + _OPTION_NAMES}
            origin = tuple(float(v) for v in d["origin_m"].reshape(-1))
            names = tuple(str(n) for n in d.get("recordings", np.array([], dtype=str)).reshape(-1))
            ray_walk = str(d["ray_walk"]) if "ray_walk" in d else None
        except (KeyError, TypeError, ValueError) as e:
            raise FileFormatError(f"{path}: missing or malformed field ({e})") from None
        if ray_walk is not None:
            try:
                check("grid", {"ray_walk": ray_walk})
            except OptionError as e:
                raise FileFormatError(f"{path}: {e}") from None
        if values.dtype != np.int32 or values.ndim != 2 or len(origin) != 2:
            raise FileFormatError(f"{path}: `evidence` must be a 2-D int32 array, origin (x, y)")
        if not all(np.isfinite(v) for v in (*origin, *scalars.values())):
            raise FileFormatError(f"{path}: cell size, origin and options must be finite")
        if scalars["cell_size_m"] <= 0:
            raise FileFormatError(f"{path}: cell_size_m must be > 0")
        return cls(values=values, origin_m=origin, recordings=names, ray_walk=ray_walk, **scalars)  # type: ignore[arg-type]


def merge_evidence(maps: Sequence[EvidenceMap]) -> EvidenceMap:
    """The exact, order-free sum of evidence maps on one cell lattice, over the union of their
    extents. Maps of different cell sizes or on shifted lattices are refused
    (:class:`~floorscan.OptionError` / :class:`~floorscan.GeometryError`), never resampled;
    so are maps with different clamps or thresholds (the merged map would be ambiguous), and
    maps whose free evidence followed different ray walks. The merged ray walk is unknown
    (None) when a map's is."""
    maps = list(maps)
    if not maps:
        raise OptionError("no evidence maps to merge")
    first = maps[0]
    for k, m in enumerate(maps[1:], start=1):
        for name in _OPTION_NAMES:
            if getattr(m, name) != getattr(first, name):
                raise OptionError(
                    f"evidence map {k} has {name} = {getattr(m, name)}, map 0 has {getattr(first, name)}: "
                    "maps made with different grid options do not merge"
                )
    walks = {m.ray_walk for m in maps}
    known = sorted(w for w in walks if w is not None)
    if len(known) > 1:
        raise OptionError(
            f"evidence maps made with ray walks {known} do not merge: each clears other cells "
            "(GridOptions.ray_walk)"
        )
    ray_walk = None if None in walks else known[0]
    names = tuple(n for m in maps for n in m.recordings)
    nonempty = [m for m in maps if m.values.size]
    if not nonempty:
        return replace(first, recordings=names, ray_walk=ray_walk)
    origin, values = _native.merge_evidence(
        [m.cell_size_m for m in nonempty],
        [tuple(m.origin_m) for m in nonempty],
        [np.ascontiguousarray(m.values, dtype=np.int32) for m in nonempty],
    )
    return replace(
        first, values=values, origin_m=tuple(origin), recordings=names, ray_walk=ray_walk
    )


def _savez_whole(f, arrays: Dict[str, np.ndarray]) -> None:
    """``np.savez`` with stop signals held until it returns: interrupted half-way, it leaves
    its ZipFile open with a writing handle, and the garbage collector's close of it prints an
    ignored exception's traceback. A signal held here stops the write as it returns (the
    temporary file is removed by :func:`write_atomic_with`)."""
    with deferred_signals():
        np.savez(f, **arrays)
