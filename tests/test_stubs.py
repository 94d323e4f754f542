"""The type stub of the native module lists exactly what the module has (so it cannot drift)."""

from __future__ import annotations

import ast
from pathlib import Path

import floorscan
from floorscan import _native

STUB = Path(floorscan.__file__).with_name("_native.pyi")


def stub_members():
    tree = ast.parse(STUB.read_text())
    classes = {}
    top = set()
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            classes[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)} - {
                "__init__",
                "__len__",
            }
        elif isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
    return classes, top


def test_stub_matches_the_native_module():
    classes, top = stub_members()
    native_classes = {n for n in dir(_native) if isinstance(getattr(_native, n), type)}
    assert set(classes) == native_classes
    for name, members in classes.items():
        cls = getattr(_native, name)
        native = {m for m in dir(cls) if not m.startswith("_")}
        assert members == native, (
            f"{name}: stub has {sorted(members - native)}, module has {sorted(native - members)}"
        )
    assert top <= set(dir(_native))
