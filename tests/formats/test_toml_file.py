"""TOML files: what floorscan writes reads back the same (tomllib), comments stay beside their
values, and bad TOML is a one-line ConfigError naming the file."""

import math

import pytest
from floorscan.errors import ConfigError
from floorscan.formats.toml_file import dumps_toml, load_toml, loads_toml


def test_written_toml_reads_back_with_comments_and_nested_tables():
    doc = {
        "name": 'a "quoted" name',
        "ranger": {"columns": 64, "threshold": 10.5, "refine": "subpixel", "mask": None},
        "map": {"origin_m": (1.0, -2.0), "limits": {"max": math.inf, "flag": True}},
    }
    text = dumps_toml(doc, {"ranger.columns": "columns per frame", "map.limits.flag": "on"})
    back = loads_toml(text)
    assert back["name"] == doc["name"]
    assert back["ranger"] == {"columns": 64, "threshold": 10.5, "refine": "subpixel"}
    assert back["map"]["origin_m"] == [1.0, -2.0]
    assert back["map"]["limits"] == {"max": math.inf, "flag": True}
    line = next(x for x in text.splitlines() if x.startswith("columns"))
    assert line.endswith("# columns per frame")
    assert "[map.limits]" in text


def test_bad_toml_names_the_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[ranger\ncolumns = 3\n")
    with pytest.raises(ConfigError, match="bad.toml: invalid TOML"):
        load_toml(path)
    with pytest.raises(ConfigError, match="missing.toml"):
        load_toml(tmp_path / "missing.toml")
