"""Each default of the Rust options types lives in exactly one place: their `impl Default`.
No Python file binds an option's name to its Rust default value (a keyword default, a
dataclass field, an assignment, an argparse default, a dict literal): Python reads them."""

from __future__ import annotations

import re
from pathlib import Path

import floorscan
from floorscan.options import KINDS, defaults

PACKAGE = Path(floorscan.__file__).parent

GENERIC = {"x", "y", "seed"}
"""Point coordinates (`origin_m.x`): every pose and quaternion has an `x = 0.0`; a random
seed's 0 (every simulation, render and noise draw takes one; the drive's is one of them)."""

OTHER_OPTIONS = {"calibration"}
"""Python-owned options that happen to share a name and value (``CalibrationOptions.max_range_m``,
the ground table's limit, is not the ranger's)."""


def leaves(d, prefix=""):
    for k, v in d.items():
        if isinstance(v, dict):
            yield from leaves(v, f"{prefix}{k}.")
        else:
            yield f"{prefix}{k}", v


def literal(v) -> str:
    if isinstance(v, str):
        return rf"[\"']{re.escape(v)}[\"']"
    if isinstance(v, float) and v.is_integer():
        return rf"{int(v)}(\.0)?\b"
    return re.escape(repr(v)) + r"\b"


def rust_defaults():
    out = {}
    for kind in KINDS:
        for key, value in leaves(defaults(kind)):
            name = key.rsplit(".", 1)[-1]
            if value is None or isinstance(value, (bool, list)) or name in GENERIC:
                continue
            out.setdefault(name, set()).add(value)
    return out


def test_no_python_file_redeclares_a_rust_default():
    names = rust_defaults()
    assert {"half_width_px", "cell_size_m", "hit_nats", "size_m"} <= set(names)
    found = []
    for path in PACKAGE.rglob("*.py"):
        if path.relative_to(PACKAGE).parts[0] in OTHER_OPTIONS:
            continue
        for n, line in enumerate(path.read_text().splitlines(), 1):
            code = line.split("#")[0]
            for name, values in names.items():
                for v in values:
                    pat = rf"[\"']?\b{name}\b[\"']?\s*(:\s*[\w\[\], .]+)?\s*[=:]\s*{literal(v)}"
                    if re.search(pat, code):
                        found.append(f"{path.relative_to(PACKAGE)}:{n}: {line.strip()}")
    assert not found, "defaults re-declared:\n" + "\n".join(found)


def test_the_check_finds_a_redeclared_default(tmp_path):
    """The pattern catches the forms the old code used."""
    names = rust_defaults()
    for line in ("half_width_px: int = 4,", '"cell_size_m": 0.04,', "size_m=3.84"):
        name = re.match(r"[\"']?(\w+)", line).group(1)
        assert any(
            re.search(rf"[\"']?\b{name}\b[\"']?\s*(:\s*[\w\[\], .]+)?\s*[=:]\s*{literal(v)}", line)
            for v in names[name]
        ), line
