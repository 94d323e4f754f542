"""Defaults in the command line's help, read from where they live: a flag that overrides a
configuration key shows the configuration's default (``(default 4, the config's
ranger.half_width_px)``), never a copy of it; a flag with an argparse default shows it with
``%(default)s``. ``tests/test_cli_grammar.py`` holds every command's help to this."""

from __future__ import annotations

from typing import Any

from ..pipeline.config import default_value


def shown(value: Any) -> str:
    """A configuration value as the help shows it (TOML's spelling of booleans and lists)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(shown(v) for v in value) + "]"
    if value is None:
        return "none"
    return str(value)


def config_default(key: str) -> str:
    """``(default V, the config's KEY)`` for a dotted configuration key with a scalar value."""
    value = default_value(key)
    if isinstance(value, dict):
        raise ValueError(f"{key} is a table: name one of its fields ({', '.join(value)})")
    return f"(default {shown(value)}, the config's {key})"
