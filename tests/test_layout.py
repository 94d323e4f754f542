"""The package layout (issue 11): stages as subpackages, no import circles (counting imports
inside functions too), few top-level modules, tests in folders named after the stages.

The import graph is read from the source with :mod:`ast`, not by importing, so an import
hidden in a function counts like one at the top of the file. Optional third-party imports
(ray, rosbags, zenoh, ...) are not part of the graph: only floorscan's own modules are.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "floorscan"
STAGES = {
    "calibration",
    "commands",
    "drive",
    "evaluation",
    "fleet",
    "formats",
    "mapping",
    "node",
    "pipeline",
    "ranging",
    "sim",
}
MAX_TOP_LEVEL_MODULES = 12


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """floorscan modules that ``path`` imports anywhere in its body."""
    is_package = path.name == "__init__.py"
    found: set[str] = set()
    tree = ast.parse(path.read_text(), str(path))
    type_only = {
        id(n)
        for block in ast.walk(tree)
        if isinstance(block, ast.If) and ast.unparse(block.test).endswith("TYPE_CHECKING")
        for n in ast.walk(block)
    }
    for node in ast.walk(tree):
        if id(node) in type_only:
            continue  # imports for annotations only are not run
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names if a.name.startswith("floorscan")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".")
                if not is_package:
                    base = base[:-1]
                base = base[: len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            elif node.module and node.module.startswith("floorscan"):
                module = node.module
            else:
                continue
            # `from pkg import sub` imports the submodule; `from pkg import name` the package
            subs = [f"{module}.{a.name}" for a in node.names if f"{module}.{a.name}" in known]
            targets = subs if len(subs) == len(node.names) else [module, *subs]
        else:
            continue
        for target in targets:
            while target not in known and "." in target:
                target = target.rsplit(".", 1)[0]
            # importing a.b.c runs a/__init__ and a/b/__init__ first: edges to them too, but
            # not to the importer's own ancestors, which Python has imported before it
            parts = target.split(".")
            for k in range(1, len(parts) + 1):
                step = ".".join(parts[:k])
                if step in known and step != name and not name.startswith(step + "."):
                    found.add(step)
    return found


def import_graph() -> dict[str, set[str]]:
    mods = modules()
    known = set(mods)
    return {name: imports_of(name, path, known) for name, path in mods.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_cycle_finder_finds_a_planted_circle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycles(graph) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_circles():
    assert cycles(import_graph()) == []


def stage_of(module: str) -> str:
    """``floorscan.mapping.grid`` -> ``mapping``; a top-level module is its own stage."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def stage_graph(graph: dict[str, set[str]]) -> dict[str, set[str]]:
    out: dict[str, set[str]] = {}
    for a, targets in graph.items():
        sa = stage_of(a)
        out.setdefault(sa, set()).update(stage_of(b) for b in targets if stage_of(b) != sa)
    return out


def test_stage_graph_finds_a_knot_between_subpackages():
    modules = {
        "floorscan.a.x": {"floorscan.b.y"},
        "floorscan.b.y": set(),
        "floorscan.b.z": {"floorscan.a.w"},
        "floorscan.a.w": set(),
    }
    assert cycles(modules) == []  # no module cycle ...
    assert cycles(stage_graph(modules)) == [["a", "b"]]  # ... but a knot of subpackages


def test_no_circles_between_subpackages():
    """A stage may use the stages below it, never one that uses it (a knot: formats ->
    mapping -> ranging -> formats made any of them impossible to understand alone). The
    message names the modules that tie each knot."""
    graph = import_graph()
    knots = cycles(stage_graph(graph))
    ties = [
        f"{a} -> {b}"
        for knot in knots
        for a, targets in sorted(graph.items())
        for b in sorted(targets)
        if stage_of(a) in knot and stage_of(b) in knot and stage_of(a) != stage_of(b)
    ]
    assert knots == [], "\n".join(ties)


def test_top_level_is_stages_and_few_modules():
    top_modules = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top_modules) <= MAX_TOP_LEVEL_MODULES, top_modules
    packages = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    assert packages == STAGES


def test_tests_mirror_the_stages():
    """tests/<stage>/ for each stage subpackage that has tests; nothing else in a folder; the
    files at the top of tests/ are about the package as a whole (errors, signals, files,
    hostile input, stubs, this layout) or shared fixtures."""
    tests = Path(__file__).parent
    folders = {p.name for p in tests.iterdir() if p.is_dir() and not p.name.startswith(("_", "."))}
    assert folders <= STAGES, folders - STAGES
    for folder in folders:
        for path in (tests / folder).iterdir():
            assert path.suffix == ".py" and path.name.startswith("test_"), path


CRATES = PACKAGE.parents[1] / "crates"


def rust_module_graph(crate: Path) -> dict[str, set[str]]:
    """Module -> modules it names (`crate::m`), per file of the crate's src/ (a folder module
    is its mod.rs with its files), test code (after `#[cfg(test)]`) left out."""
    src = crate / "src"
    graph: dict[str, set[str]] = {}
    for path in sorted(src.rglob("*.rs")):
        rel = path.relative_to(src).with_suffix("")
        # a stage folder's file is its module (re-exported at the crate root: `crate::ranger`),
        # its mod.rs the folder's
        name = rel.parts[-2] if rel.name == "mod" else rel.parts[-1]
        if name in ("lib", "main") or name.endswith("_tests"):
            continue
        text = path.read_text().split("#[cfg(test)]")[0]
        text = re.sub(r"//[^\n]*", "", text)  # doc links are not dependencies
        found = set(re.findall(r"\bcrate::(\w+)", text)) - {name}
        graph.setdefault(name, set()).update(found)
    return graph


def test_no_module_circles_in_the_rust_crates():
    for crate in sorted(p for p in CRATES.iterdir() if (p / "src").is_dir()):
        assert cycles(rust_module_graph(crate)) == [], crate.name
