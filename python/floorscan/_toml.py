"""TOML reading (tomllib, or tomli before Python 3.11) and a small writer for flat tables of
numbers, strings, booleans and lists (all floorscan writes)."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any, Dict

from .errors import ConfigError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def load_toml(path: Path) -> Dict[str, Any]:
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except OSError as e:
        raise ConfigError(f"cannot read {path}: {e}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise ConfigError(f"{path}: invalid TOML: {e}") from None


def loads_toml(text: str, *, source: str = "<toml>") -> Dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"{source}: invalid TOML: {e}") from None


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def dumps_toml(doc: Dict[str, Any], comments: Dict[str, str] | None = None) -> str:
    """Top-level scalars first, then one ``[table]`` per dict (one level, plus nested tables
    written as ``[a.b]``). ``comments`` maps ``table.key`` to a trailing comment."""
    comments = comments or {}
    lines = []

    def emit(prefix: str, table: Dict[str, Any]) -> None:
        for k, v in table.items():
            if isinstance(v, dict) or v is None:
                continue
            c = comments.get(f"{prefix}{k}")
            lines.append(f"{k} = {_value(v)}" + (f"  # {c}" if c else ""))
        for k, v in table.items():
            if isinstance(v, dict):
                lines.append("")
                lines.append(f"[{prefix}{k}]")
                emit(f"{prefix}{k}.", v)

    emit("", doc)
    return "\n".join(lines).lstrip("\n") + "\n"
