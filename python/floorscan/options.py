"""Options of the Rust components as Python sees them: dicts of the core's serde form.

The defaults, the field docs and every check live in the Rust options types
(``crates/floorscan-core/src/*_options.rs``, ``inserter.rs``, ``local_map.rs``); this module
only reads them through the binding, and turns numpy values into plain ones on the way in.

>>> defaults("ranger")["refinement"]
'step'
>>> sorted(field_docs("inserter"))[:2]
['boundary_margin_rows', 'laser']
"""

from __future__ import annotations

import re
from typing import Any, Callable, Dict, List, Tuple

import numpy as np

from ._native import drive, mapping, ranging
from .errors import OptionError

KINDS: Dict[str, Callable[[], Dict[str, Any]]] = {
    "ranger": ranging.default_ranger_options,
    "appearance": ranging.default_appearance_options,
    "grid": mapping.default_grid_options,
    "inserter": mapping.default_inserter_options,
    "local_map": mapping.default_local_map_options,
    "scan_matcher": mapping.default_scan_matcher_options,
    "slam": mapping.default_slam_options,
    "pose_graph": mapping.default_pose_graph_options,
    "parallax": ranging.default_parallax_options,
    "fusion": ranging.default_fusion_options,
    "avoidance_map": drive.default_avoidance_map_options,
    "visual_sensor_model": drive.default_visual_sensor_model,
    "drive": drive.default_drive_map_options,
    "drive_run": drive.default_drive_run_options,
    "costmap": drive.default_costmap_options,
    "dwa": drive.default_dwa_options,
}
"""Each options type by its name, with its defaults function."""

CHECKS: Dict[str, Callable[[Dict[str, Any]], Dict[str, Any]]] = {
    "ranger": ranging.check_ranger_options,
    "appearance": ranging.check_appearance_options,
    "grid": mapping.check_grid_options,
    "inserter": mapping.check_inserter_options,
    "local_map": mapping.check_local_map_options,
    "scan_matcher": mapping.check_scan_matcher_options,
    "slam": mapping.check_slam_options,
    "pose_graph": mapping.check_pose_graph_options,
    "parallax": ranging.check_parallax_options,
    "fusion": ranging.check_fusion_options,
    "avoidance_map": drive.check_avoidance_map_options,
    "visual_sensor_model": drive.check_visual_sensor_model,
    "drive": drive.check_drive_map_options,
    "drive_run": drive.check_drive_run_options,
    "costmap": drive.check_costmap_options,
    "dwa": drive.check_dwa_options,
}
"""Each options type's check: a dict of any of its fields in, every field out (validated)."""

SCHEMAS: Dict[str, Callable[[], Dict[str, Any]]] = {
    "ranger": ranging.ranger_options_schema,
    "appearance": ranging.appearance_options_schema,
    "grid": mapping.grid_options_schema,
    "inserter": mapping.inserter_options_schema,
    "local_map": mapping.local_map_options_schema,
    "scan_matcher": mapping.scan_matcher_options_schema,
    "slam": mapping.slam_options_schema,
    "pose_graph": mapping.pose_graph_options_schema,
    "parallax": ranging.parallax_options_schema,
    "fusion": ranging.fusion_options_schema,
    "avoidance_map": drive.avoidance_map_options_schema,
    "visual_sensor_model": drive.visual_sensor_model_schema,
    "drive": drive.drive_map_options_schema,
    "drive_run": drive.drive_run_options_schema,
    "costmap": drive.costmap_options_schema,
    "dwa": drive.dwa_options_schema,
}


def defaults(kind: str) -> Dict[str, Any]:
    """The default options of ``kind`` (a key of :data:`KINDS`), from Rust ``impl Default``."""
    return KINDS[kind]()


def check(kind: str, options: Dict[str, Any]) -> Dict[str, Any]:
    """``options`` completed with the defaults and validated by the Rust type (OptionError).
    A nested table given in part (``[sensors.visual]`` with ``hit_nats`` only) keeps the
    default of its other fields.

    >>> check("ranger", {"threshold": "abc"})
    Traceback (most recent call last):
    ...
    floorscan.errors.OptionError: invalid option `threshold`: expected a number, got 'abc'
    """
    given = merged(defaults(kind), plain(options))
    try:
        return CHECKS[kind](given)
    except OptionError as e:
        raise in_user_words(kind, given, e) from None


TYPE_ERRORS = re.compile(
    r"^(TypeError|OverflowError|ValueError): |^expected either |^invalid type: "
    r"|^data did not match any variant"
)
"""How pythonize and serde word a value of the wrong type (Python's words, not the user's)."""


def in_user_words(kind: str, given: Dict[str, Any], error: OptionError) -> OptionError:
    """``error`` with a wrong value type said as what was expected, from the default's type
    (``expected a number, got 'abc'``); any other error unchanged."""
    m = re.match(r"^invalid option `([^`]+)`: (.*)$", str(error))
    if m is None or not TYPE_ERRORS.search(m.group(2)):
        return error
    path = re.findall(r"[^.\[\]]+", m.group(1))
    default: Any = defaults(kind)
    value: Any = given
    try:
        for p in path:
            key: Any = int(p) if p.isdigit() else p
            default, value = default[key], value[key]
    except (KeyError, IndexError, TypeError):
        return error
    values = re.findall(r"One of: (.*)\.$", field_docs(kind).get(m.group(1), ""))
    forms = _forms(kind, path) if "untagged enum" in m.group(2) else ""
    expected = forms or _expected(default, values)
    return OptionError(f"invalid option `{m.group(1)}`: expected {expected}, got {value!r}")


def _forms(kind: str, path: List[str]) -> str:
    """The forms an untagged enum field takes, from its schema (``a whole number or a list or
    a table of obstacle_width_m, range_m``); "" if the schema does not say."""
    schema = SCHEMAS[kind]()
    defs = schema.get("$defs", {})
    node: Any = schema
    for p in path:
        node = node.get("properties", {}).get(p)
        if node is None:
            return ""
        while "$ref" in node:
            node = defs[node["$ref"].rsplit("/", 1)[-1]]
    words = {"integer": "a whole number", "number": "a number", "array": "a list"}
    forms = []
    for alt in node.get("anyOf", []):
        if alt.get("type") == "object":
            forms.append("a table of " + ", ".join(alt.get("properties", {})))
        elif alt.get("type") in words:
            forms.append(words[alt["type"]])
    return " or ".join(forms)


def _expected(default: Any, values: List[str]) -> str:
    if values:
        return "one of " + values[0]
    if isinstance(default, bool):
        return "true or false"
    if isinstance(default, int):
        return "a whole number" + (" >= 0" if default >= 0 else "")
    if isinstance(default, float):
        return "a number"
    if isinstance(default, str):
        return "a string"
    if isinstance(default, list):
        return f"a list like {default}"
    if isinstance(default, dict):
        return "a table of " + ", ".join(default)
    return f"a value like {default!r}"


def _enum_values(node: Dict[str, Any]) -> Tuple[str, ...]:
    """The values of a schema node that is an enum of plain values: schemars writes
    ``enum`` for variants without docs and ``oneOf`` of ``const`` for documented ones."""
    if "enum" in node:
        return tuple(node["enum"])
    return tuple(alt["const"] for alt in node.get("oneOf", []) if "const" in alt)


def choices(kind: str, name: str) -> Tuple[str, ...]:
    """The values the enum field ``name`` of ``kind`` takes, from its schema (``()`` if it is
    no enum of plain values).

    >>> choices("drive_run", "sensor")
    ('camera', 'laser')
    """
    schema = SCHEMAS[kind]()
    node: Any = schema.get("properties", {}).get(name, {})
    while "$ref" in node:
        node = schema.get("$defs", {})[node["$ref"].rsplit("/", 1)[-1]]
    return _enum_values(node)


def merged(base: Any, given: Any) -> Any:
    """``given`` over ``base``, recursively where ``given`` is a dict whose keys are all keys of
    the dict ``base`` (a struct given in part); anything else replaces (an enum's other variant,
    a list, a number)."""
    if isinstance(base, dict) and isinstance(given, dict) and set(given) <= set(base):
        return {**base, **{k: merged(base[k], v) for k, v in given.items()}}
    return given


def field_docs(kind: str) -> Dict[str, str]:
    """Dotted field name -> its Rust doc comment (first paragraph), nested structs included."""
    schema = SCHEMAS[kind]()
    defs = schema.get("$defs", {})
    out: Dict[str, str] = {}

    def resolve(node: Dict[str, Any]) -> Dict[str, Any]:
        ref = node.get("$ref")
        if ref is None:
            for alt in node.get("anyOf", []) + node.get("oneOf", []):
                if "$ref" in alt:
                    return resolve(alt)
            return node
        return resolve(defs[ref.rsplit("/", 1)[-1]])

    def walk(node: Dict[str, Any], prefix: str) -> None:
        for name, prop in resolve(node).get("properties", {}).items():
            target = resolve(prop)
            doc = " ".join((prop.get("description") or target.get("description", "")).split())
            doc = without_doc_links(doc)
            values = _enum_values(target)
            if values:
                doc += f" One of: {' | '.join(values)}."
            out[prefix + name] = doc
            if "properties" in target:
                walk(prop, prefix + name + ".")

    walk(schema, "")
    return out


def without_doc_links(doc: str) -> str:
    """A Rust doc comment's intra-doc links as plain text: ``[`crate::Error::OutOfBounds`]``
    names the Python class of that error (``OutOfBoundsError``), ``[`crate::x::Name`]`` is
    ``Name``, ``[text](target)`` is ``text``.

    >>> without_doc_links("is an [`crate::Error::OutOfBounds`], see [`grid::Grid`]")
    'is an `OutOfBoundsError`, see `Grid`'
    """

    def name(m: re.Match) -> str:
        path = m.group(1).split("::")
        if len(path) >= 2 and path[-2] == "Error":
            return f"`{path[-1]}Error`"
        return f"`{path[-1]}`"

    doc = re.sub(r"\[(`?[^\]]*`?)\]\([^)]*\)", lambda m: m.group(1), doc)
    return re.sub(r"\[`([^`\]]+)`\]", name, doc)


def plain(value: Any) -> Any:
    """numpy arrays and scalars as lists and Python numbers, recursively (serde reads those)."""
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value


class OptionsObject:
    """A Rust options type as a read-only Python object: keyword arguments are any of its
    fields, the others take the Rust defaults, a bad one is an :class:`OptionError` naming
    it; attribute access; ``replace(**changes)`` makes a changed copy; ``to_dict()`` gives
    every field. A subclass names its type: ``class X(OptionsObject, kind="avoidance_map")``.
    """

    __slots__ = ("_values",)
    _kind = ""

    def __init_subclass__(cls, *, kind: str = "", **kw: Any) -> None:
        super().__init_subclass__(**kw)
        if kind:
            cls._kind = kind

    def __init__(self, **options: Any) -> None:
        object.__setattr__(self, "_values", check(self._kind, options))

    def __getattr__(self, name: str) -> Any:
        try:
            return object.__getattribute__(self, "_values")[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"{type(self).__name__} is read-only: use replace(...)")

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self._values == other._values

    def __hash__(self) -> int:
        return hash(repr(sorted(self._values.items())))

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in self._values.items())
        return f"{type(self).__name__}({fields})"

    def to_dict(self) -> Dict[str, Any]:
        """Every field (the serde form)."""
        return dict(self._values)

    def replace(self, **changes: Any):
        return type(self)(**{**self._values, **changes})
