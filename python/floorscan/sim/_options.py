"""Shared helper of the simulator's option classes: frozen, keyword-only, validated by the
Rust core on construction (one source of truth for ranges and defaults)."""

from __future__ import annotations

import dataclasses
import json
from typing import Any, Callable, Dict


def init_options(obj: Any, validate: Callable[[str], None], given: Dict[str, Any]) -> None:
    """Sets the dataclass fields of ``obj`` from ``given`` (defaults for the rest), then asks
    the core to validate them (``validate``: the component's typed binding, JSON in)."""
    for f in dataclasses.fields(obj):
        value = given.get(f.name, f.default)
        if (
            isinstance(value, (int, float))
            and not isinstance(value, bool)
            and f.type in ("float", float)
        ):
            value = float(value)
        object.__setattr__(obj, f.name, value)
    validate(json.dumps(as_dict(obj)))


def as_dict(obj: Any) -> Dict[str, Any]:
    """Fields as a plain dict (nested option objects included)."""
    return dataclasses.asdict(obj)
