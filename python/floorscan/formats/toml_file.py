"""TOML files: reading with tomllib (tomli before Python 3.11), writing with tomlkit (comments
kept beside their values)."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path
from typing import Any, Dict

import tomlkit

from ..errors import ConfigError

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


COMMENT_AFTER_MAX = 60
"""Longest comment written after its value; longer ones go above the key, wrapped."""

COMMENT_WIDTH = 94
"""Width of wrapped comment lines."""


def dumps_toml(doc: Dict[str, Any], comments: Dict[str, str] | None = None) -> str:
    """Writes ``doc`` with tomlkit: scalars and lists, one ``[table]`` per dict (nested tables
    as ``[a.b]``), None values left out. ``comments`` maps ``table.key`` to a comment: written
    after the value when short, as comment lines above the key when longer than
    ``COMMENT_AFTER_MAX`` characters."""
    comments = comments or {}

    def fill(container, prefix: str, table: Dict[str, Any]) -> None:
        for k, v in table.items():
            if isinstance(v, dict) or v is None:
                continue
            item = tomlkit.item(list(v) if isinstance(v, tuple) else v)
            c = comments.get(f"{prefix}{k}")
            if c and len(c) <= COMMENT_AFTER_MAX:
                item.comment(c)
                item.trivia.comment_ws = "  "
            elif c:
                for line in textwrap.wrap(c, COMMENT_WIDTH):
                    container.add(tomlkit.comment(line))
            container.add(k, item)
        for k, v in table.items():
            if isinstance(v, dict):
                sub = tomlkit.table()
                fill(sub, f"{prefix}{k}.", v)
                container.add(k, sub)

    document = tomlkit.document()
    fill(document, "", doc)
    return tomlkit.dumps(document)
