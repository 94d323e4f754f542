"""What a fleet job maps: recordings, each with its own calibration and configuration (a
fleet of different robots), given on the command line as ``REC`` or ``REC::TABLE`` or in a
fleet TOML file (docs/fleet.md)::

    [defaults]                    # optional: for every recording that does not say
    table = "tables/robot-a.json"
    config = "floorscan.toml"

    [[recording]]
    input = "day1/"               # anything `floorscan run` accepts
    name = "day1"                 # output folder DIR/<name>/ (default: the input's name)
    table = "tables/robot-b.json" # or calibrate = "pattern.png" (+ pattern = "pattern.toml")
    odometry = "day1.tum"         # for a video

Relative paths in the file are relative to the file's folder.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Dict, List, Optional, Sequence

from .._atomic import PathLike
from ..errors import ConfigError, OptionError
from ..formats.toml_file import load_toml

SEPARATOR = "::"
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,99}$")
RESERVED_NAMES = ("merged",)


@dataclass(frozen=True)
class Recording:
    """One recording of a fleet job and what ``floorscan run`` needs to map it."""

    input: str
    name: str = ""
    table: Optional[str] = None
    config: Optional[str] = None
    calibrate: Optional[str] = None
    pattern: Optional[str] = None
    odometry: Optional[str] = None

    def run_argv(self, out_dir: PathLike) -> List[str]:
        """The ``floorscan run`` command line that maps this recording into ``out_dir``."""
        argv = ["run", self.input, "-o", str(out_dir)]
        for flag, value in (
            ("--table", self.table),
            ("--config", self.config),
            ("--calibrate", self.calibrate),
            ("--pattern", self.pattern),
            ("--odometry", self.odometry),
        ):
            if value is not None:
                argv += [flag, value]
        return argv


_KEYS = {f.name for f in fields(Recording)}


def parse_recording(text: str) -> Recording:
    """``REC`` or ``REC::TABLE``."""
    if SEPARATOR in text:
        rec, table = text.rsplit(SEPARATOR, 1)
        if not rec or not table:
            raise OptionError(f"recording {text!r}: expected REC or REC::TABLE")
        return Recording(input=rec, table=table)
    return Recording(input=text)


def read_fleet_toml(path: PathLike) -> List[Recording]:
    """The recordings of a fleet TOML file (format above), paths resolved."""
    path = Path(path)
    doc = load_toml(path)
    unknown = set(doc) - {"defaults", "recording"}
    if unknown:
        raise ConfigError(
            f"{path}: unknown table `{sorted(unknown)[0]}` (known: defaults, recording)"
        )
    base = path.parent
    defaults = _entry(doc.get("defaults", {}), path, "defaults", base, need_input=False)
    entries = doc.get("recording", [])
    if not isinstance(entries, list) or not entries:
        raise ConfigError(f"{path}: no [[recording]] entries")
    out = []
    for k, e in enumerate(entries):
        values = {**defaults, **_entry(e, path, f"recording[{k}]", base, need_input=True)}
        out.append(Recording(**values))
    return out


def _entry(e, path: Path, where: str, base: Path, *, need_input: bool) -> Dict[str, str]:
    if not isinstance(e, dict):
        raise ConfigError(f"{path}: `{where}` must be a table")
    for k, v in e.items():
        if k not in _KEYS or (k in ("input", "name") and not need_input):
            raise ConfigError(
                f"{path}: unknown key `{where}.{k}` (known: {', '.join(sorted(_KEYS))})"
            )
        if not isinstance(v, str) or not v:
            raise ConfigError(f"{path}: `{where}.{k}` must be a non-empty string")
    if need_input and "input" not in e:
        raise ConfigError(f"{path}: `{where}` has no `input`")
    return {k: (v if k == "name" else str(base / v)) for k, v in e.items()}


def with_defaults(
    recordings: Sequence[Recording], *, table: Optional[str] = None, config: Optional[str] = None
) -> List[Recording]:
    """Fills each recording's missing table / config with the job's, and gives every one a
    unique output name (the input's name, then ``-2``, ``-3``... on clashes)."""
    out: List[Recording] = []
    used = set()
    for r in recordings:
        r = replace(r, table=r.table or table, config=r.config or config)
        name = r.name or _stem(r.input)
        if not _NAME.match(name) or name in RESERVED_NAMES:
            raise OptionError(
                f"recording {r.input!r}: name {name!r} must be letters, digits, '.', '_' or '-' "
                f"and not {', '.join(RESERVED_NAMES)} (set `name` in the fleet file)"
            )
        if r.name and name in used:
            raise OptionError(f"two recordings are named {name!r}")
        base, k = name, 2
        while name in used:
            name, k = f"{base}-{k}", k + 1
        used.add(name)
        out.append(replace(r, name=name))
    return out


def _stem(path: str) -> str:
    p = Path(path.rstrip("/"))
    stem = p.stem if p.suffix and not p.is_dir() else p.name
    return re.sub(r"[^A-Za-z0-9._-]", "_", stem).lstrip("._-") or "recording"
