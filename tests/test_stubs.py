"""The type stubs of `floorscan._native` are generated from the bindings (crates/floorscan-stubgen,
pyo3-introspection: signatures with parameter names, defaults and types) and must not drift:
regenerating them gives the committed files, and a changed signature is caught."""

from __future__ import annotations

import ast
import shutil
import subprocess
from pathlib import Path

import floorscan
import pytest
from floorscan import _native

STUBS = Path(floorscan.__file__).with_name("_native")
ROOT = Path(__file__).resolve().parents[1]


def stubgen(*args: str) -> subprocess.CompletedProcess:
    if shutil.which("cargo") is None:
        pytest.skip("cargo is not installed")
    return subprocess.run(
        ["cargo", "run", "-q", "-p", "floorscan-stubgen", "--", _native.__file__, *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
    )


def test_committed_stubs_are_the_generated_ones(tmp_path):
    done = stubgen(str(tmp_path))
    assert done.returncode == 0, done.stderr
    generated = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*.pyi"))
    committed = sorted(p.relative_to(STUBS) for p in STUBS.rglob("*.pyi"))
    assert generated == committed
    for rel in generated:
        assert (tmp_path / rel).read_text() == (STUBS / rel).read_text(), f"{rel} is stale"
    assert stubgen(str(STUBS), "--check").returncode == 0


def test_a_changed_signature_is_drift(tmp_path):
    """The check compares signatures, not names: rename one parameter of a committed copy."""
    copy = tmp_path / "stubs"
    shutil.copytree(STUBS, copy)
    ranging = copy / "ranging.pyi"
    text = ranging.read_text()
    assert "image_height" in text
    ranging.write_text(text.replace("image_height", "height_px", 1))
    done = stubgen(str(copy), "--check")
    assert done.returncode == 1
    assert "ranging.pyi differs from the bindings" in done.stderr and "height_px" in done.stderr


def test_stubs_name_every_member_of_every_submodule():
    """Each submodule's classes and functions appear in its stub (and import by full name)."""
    for name in ("ranging", "mapping", "sim"):
        module = __import__(f"floorscan._native.{name}", fromlist=["_"])
        tree = ast.parse((STUBS / f"{name}.pyi").read_text())
        declared = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))} | {
            n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)
        }
        public = {m for m in dir(module) if not m.startswith("__")}
        assert public <= declared, f"{name}: stub lacks {sorted(public - declared)}"
