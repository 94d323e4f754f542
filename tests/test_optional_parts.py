"""Tests skip, never fail, on a missing optional part (issue 37): every optional module a test
file imports, anywhere in it, is named by a skip check of that file (``pytest.importorskip``,
a hostile case's ``needs``, or ``require_ros1``, which checks ``ROS1_MODULES``); and the ROS 1
node's own optional imports are among what ``require_ros1`` checks.

Read from the source with :mod:`ast`, as tests/test_layout.py reads imports: an import hidden
in a test function counts like one at the top of the file.
"""

from __future__ import annotations

import ast
from pathlib import Path

from ros1_fixtures import ROS1_MODULES

TESTS = Path(__file__).parent
PACKAGE = TESTS.parent / "python" / "floorscan"

OPTIONAL = {
    "rospy",
    "rosgraph",
    "genpy",
    "sensor_msgs",
    "nav_msgs",
    "tf2_msgs",
    "geometry_msgs",
    "std_msgs",
    "ray",
    "zenoh",
    "foxglove",
    "websockets",
    "google.protobuf",
    "rosbags",
    "rerun",
}
"""Modules a machine may lack: ROS 1 (Debian's packages, possibly in part), the extras
(ray, eclipse-zenoh, foxglove-sdk and its client's websockets and protobuf, rerun-sdk), and
rosbags (a dependency, but a missing one costs only the bags)."""


def is_optional(module: str) -> bool:
    return any(module == m or module.startswith(m + ".") for m in OPTIONAL)


def imported(tree: ast.AST) -> set:
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.add(node.module)
    return {m for m in found if is_optional(m)}


def skip_checked(tree: ast.AST) -> set:
    """Module names the file's skip checks name."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            func = node.func.attr if isinstance(node.func, ast.Attribute) else node.func
            name = func if isinstance(func, str) else getattr(func, "id", "")
            if name == "importorskip" and node.args and isinstance(node.args[0], ast.Constant):
                names.add(node.args[0].value)
            if name == "require_ros1":
                names.update({"rospy", *ROS1_MODULES})
            for kw in node.keywords:
                if kw.arg == "needs" and isinstance(kw.value, (ast.Tuple, ast.List)):
                    names.update(e.value for e in kw.value.elts if isinstance(e, ast.Constant))
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "ROS1_MODULES" for t in node.targets
        ):
            names.update(e.value for e in ast.walk(node.value) if isinstance(e, ast.Constant))
    return names


def covered(module: str, checks: set) -> bool:
    """``sensor_msgs.msg`` is covered by a check of ``sensor_msgs`` or of ``sensor_msgs.msg``;
    ``sensor_msgs`` by a check of ``sensor_msgs.msg`` too (importing it imports its package)."""
    return any(
        module == c or module.startswith(c + ".") or c.startswith(module + ".") for c in checks
    )


def unchecked(source: str) -> set:
    tree = ast.parse(source)
    checks = skip_checked(tree)
    return {m for m in imported(tree) if not covered(m, checks)}


def test_every_optional_module_a_test_imports_is_in_its_skip_check():
    missing = {}
    for path in sorted(TESTS.rglob("*.py")):
        gaps = unchecked(path.read_text())
        if gaps:
            missing[str(path.relative_to(TESTS))] = sorted(gaps)
    assert missing == {}


def test_the_ros1_skip_check_covers_the_nodes_own_imports():
    node = imported(ast.parse((PACKAGE / "node" / "ros1.py").read_text()))
    node |= imported(ast.parse((PACKAGE / "node" / "messages.py").read_text()))
    assert node, "the ROS 1 node imports no optional module: this test checks nothing"
    checks = {"rospy", *ROS1_MODULES}
    assert {m for m in node if not covered(m, checks)} == set()
    assert "tf2_msgs.msg" in ROS1_MODULES  # the module a partial ROS 1 lacked (issue 37)


def test_the_check_finds_a_planted_unchecked_import():
    planted = (
        "import pytest\n"
        "rospy = pytest.importorskip('rospy')\n"
        "def test_x():\n"
        "    from tf2_msgs.msg import TFMessage\n"
        "    from sensor_msgs.msg import Image\n"
        "    import numpy\n"
    )
    assert unchecked(planted) == {"tf2_msgs.msg", "sensor_msgs.msg"}
    with_ros1 = planted.replace("rospy = pytest.importorskip('rospy')", "require_ros1()")
    assert unchecked(with_ros1) == set()
    assert unchecked("import ray\n") == {"ray"}
    assert unchecked("def f():\n    from ray import remote\n") == {"ray"}
