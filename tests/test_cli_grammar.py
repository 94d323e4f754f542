"""One grammar for the whole command line (issue 37): every command that writes takes
-o/--output and --force and overwrites nothing without --force; every default the help shows is
the configuration's (as `floorscan config --default` prints it) or the option's own; errors
name the file and say what was expected in the user's words.

The help is read as `floorscan COMMAND --help` shows it (argparse's own expansion of each
option's help), the configuration's defaults from the TOML that `floorscan config --default`
prints, parsed here with tomllib.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import re
from pathlib import Path

import pytest
from floorscan.cli import build_parser, main
from floorscan.pipeline.config import default_value
from floorscan.sim import World

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib

NON_WRITING = {"config"}
"""Commands that write nothing but stdout."""

CONFIG_REF = re.compile(r"\(default ([^()]*?), the config's ([a-z_.]+)\)")
DICT_REF = re.compile(r"\(default: [^()]*the config's ([a-z_.]+)\)")
DEFAULT_WORD = re.compile(r"(?<![-\w])(?<!the )default\b")
"""A default stated (not "--default", not "the default configuration")."""


def subcommands(parser: argparse.ArgumentParser | None = None) -> dict:
    parser = parser or build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def shown_help(p: argparse.ArgumentParser, action: argparse.Action) -> str:
    """An option's help as --help prints it, on one line."""
    return " ".join(p._get_formatter()._expand_help(action).split())


def options(p: argparse.ArgumentParser):
    for a in p._actions:
        if a.help and a.help != argparse.SUPPRESS and not isinstance(a, argparse._HelpAction):
            yield a, shown_help(p, a)


@pytest.fixture(scope="module")
def default_toml() -> dict:
    """`floorscan config --default`, parsed (module-wide: capsys is per test)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["config", "--default"]) == 0
    return tomllib.loads(out.getvalue())


def lookup(table: dict, key: str):
    node = table
    for part in key.split("."):
        node = node[part]
    return node


def value_of(text: str):
    """A value as written in the help, read as TOML would (2.0, true, [0.0, 0.0]); a bare
    word is a string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return "inf" if text == "inf" else text


def leaves(value):
    if isinstance(value, dict):
        for v in value.values():
            yield from leaves(v)
    else:
        yield value


def help_problems(parser: argparse.ArgumentParser, config: dict) -> list:
    """Every shown default that is not the configuration's or the option's own."""
    problems = []
    for name, p in subcommands(parser).items():
        for action, text in options(p):
            where = f"{name} {'/'.join(action.option_strings) or action.dest}"
            if "{" in text or "}" in text:
                problems.append(f"{where}: a dict or a placeholder in the help: {text}")
            refs = CONFIG_REF.findall(text)
            for shown, key in refs:
                try:
                    expected = lookup(config, key)
                except KeyError:
                    problems.append(f"{where}: no config key {key}")
                    continue
                if value_of(shown) != expected or value_of(shown) != default_value(key):
                    problems.append(f"{where}: shows {shown}, {key} is {expected!r}")
            for key in DICT_REF.findall(text):
                for leaf in leaves(lookup(config, key)):
                    if str(leaf) not in text:
                        problems.append(f"{where}: {key}'s {leaf} not in: {text}")
            own = action.default
            if own not in (None, False, argparse.SUPPRESS) and action.nargs != 0:
                if not re.search(rf"\(default {re.escape(str(own))}[),;]", text):
                    problems.append(f"{where}: default {own!r} not shown as such: {text}")
            for m in DEFAULT_WORD.finditer(text):
                rest = text[m.start() - 1 :]
                if not rest.startswith("(default"):
                    problems.append(f"{where}: 'default' outside '(default ...)': {text}")
                elif rest.startswith("(default:"):
                    free = rest[: rest.find(")") + 1]
                    if re.search(r"\d", free) and not DICT_REF.match(free):
                        problems.append(f"{where}: a number in a free-text default: {free}")
                elif not (
                    CONFIG_REF.match(rest) or re.match(rf"\(default {re.escape(str(own))}", rest)
                ):
                    problems.append(f"{where}: a default neither the config's nor its own: {text}")
    return problems


def test_every_help_default_is_the_configurations_or_the_options_own(default_toml, capsys):
    parser = build_parser()
    for name in subcommands(parser):
        with pytest.raises(SystemExit) as e:
            main([name, "--help"])
        assert e.value.code == 0
        assert capsys.readouterr().out.startswith(f"usage: floorscan {name}")
    assert help_problems(parser, default_toml) == []
    # the case the issue found: a dict shown as --bottom-margin's default
    scan = subcommands(parser)["scan"]
    margin = next(a for a in scan._actions if "--bottom-margin" in a.option_strings)
    shown = CONFIG_REF.search(shown_help(scan, margin))
    assert shown is not None
    assert int(shown.group(1)) == default_toml["ranger"]["start"]["bottom_margin"]


def test_the_help_check_finds_planted_mistakes(default_toml):
    parser = argparse.ArgumentParser(prog="x")
    sub = parser.add_subparsers()
    p = sub.add_parser("planted")
    p.add_argument("--a", help="(default 99, the config's ranger.half_width_px)")
    p.add_argument("--b", help="(default {'bottom_margin': 2})")
    p.add_argument("--c", type=int, default=7, help="(default 8)")
    p.add_argument("--d", help="rows; default 3")
    p.add_argument("--e", default="x", help="no default shown")
    p.add_argument("--f", help="(default: 3 things)")
    p.add_argument("--g", help="(default 4, the config's ranger.half_width_px)")  # right
    found = "\n".join(help_problems(parser, default_toml))
    for option in ("--a", "--b", "--c", "--d", "--e", "--f"):
        assert f"planted {option}:" in found
    assert "planted --g:" not in found


def test_every_writing_command_takes_output_and_force():
    commands = subcommands()
    assert set(commands) >= {"scan", "run", "sim", "drive", "config"}
    for name, p in commands.items():
        flags = {s for a in p._actions for s in a.option_strings}
        if name in NON_WRITING:
            assert "--output" not in flags, name
            continue
        assert {"-o", "--output", "--force"} <= flags, name
        for a in p._actions:
            if "-o" in a.option_strings:
                assert a.option_strings == ["-o", "--output"] and a.dest == "output", name


def minimal_argv(name: str, p: argparse.ArgumentParser, output: Path) -> list:
    """The command with its required arguments filled with inputs that do not exist: a
    command that read them would fail on them, so a refusal shows no work was done."""
    argv = [name]
    for a in p._actions:
        if a.option_strings and a.required:
            argv += [a.option_strings[-1], a.choices[0] if a.choices else "missing-input"]
        elif not a.option_strings and a.nargs not in ("?", "*", argparse.SUPPRESS):
            if not isinstance(a, argparse._SubParsersAction):
                argv.append("missing-input")
    return argv + ["-o", str(output)]


@pytest.mark.parametrize("name", sorted(set(subcommands()) - NON_WRITING))
def test_nothing_is_overwritten_without_force(name, tmp_path, capsys):
    p = subcommands()[name]
    kinds = p.get_default("outputs")
    target = tmp_path / "existing"
    if kinds["output"] == "folder":
        target.mkdir()
        (target / "old.txt").write_text("kept")
    else:
        target.write_text("kept")
    assert main(minimal_argv(name, p, target)) == 1
    err = capsys.readouterr().err
    assert f"{target} exists" in err and "pass --force" in err
    assert "overwrite=True" not in err
    kept = target / "old.txt" if target.is_dir() else target
    assert kept.read_text() == "kept"


def tiny_sim(out: Path, *flags: str) -> list:
    return [
        "sim",
        "--seconds",
        "0.2",
        "--width",
        "32",
        "--height",
        "24",
        "--calibration",
        "none",
        "--no-truth",
        *flags,
        str(out),
    ]


def test_sim_takes_output_keeps_out_and_refuses_an_existing_folder(tmp_path, capsys):
    assert main(tiny_sim(tmp_path / "a", "-o")) == 0
    assert (tmp_path / "a" / "images.txt").is_file()
    assert main(tiny_sim(tmp_path / "b", "--out")) == 0  # old scripts still work
    assert (tmp_path / "b" / "images.txt").is_file()
    capsys.readouterr()
    assert main(tiny_sim(tmp_path / "a", "-o")) == 1
    err = capsys.readouterr().err
    assert "pass --force" in err and "overwrite=True" not in err
    (tmp_path / "a" / "extra.txt").write_text("x")
    assert main(tiny_sim(tmp_path / "a", "--force", "-o")) == 0
    assert (tmp_path / "a" / "images.txt").is_file()
    with pytest.raises(SystemExit):
        main(["sim", "--help"])
    assert not re.search(r"--out\b", capsys.readouterr().out)  # the alias is not advertised


def test_an_unknown_world_lists_the_built_in_ones(tmp_path, capsys):
    assert main(["sim", "--world", "nowhere", "-o", str(tmp_path / "x")]) == 1
    err = capsys.readouterr().err
    assert "nowhere" in err and all(n in err for n in World.builtin_names())
    assert not (tmp_path / "x").exists()


def test_a_bad_ground_table_is_named(tmp_path, capsys):
    table = tmp_path / "broken-table.json"
    table.write_text('{"format": "something else"}')
    argv = ["scan", "--table", str(table), "frame.png", "-o", str(tmp_path / "s.csv")]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert str(table) in err and "ground table" in err


@pytest.mark.parametrize(
    "table, value, expected",
    [
        ("ranger", '"abc"', "expected a number, got 'abc'"),
        ("grid", '"big"', "expected a number, got 'big'"),
        ("ranger", "2.5", None),  # threshold 2.5 is valid
    ],
)
def test_a_wrong_value_type_is_said_in_the_users_words(tmp_path, capsys, table, value, expected):
    key = {"ranger": "threshold", "grid": "cell_size_m"}[table]
    cfg = tmp_path / "c.toml"
    cfg.write_text(f"[{table}]\n{key} = {value}\n")
    rc = main(["config", "--check", str(cfg)])
    out = capsys.readouterr()
    if expected is None:
        assert rc == 0 and f"{key} = {value}" in out.out
        return
    assert rc == 1
    assert f"{cfg}: invalid option `{table}.{key}`: {expected}" in out.err
    assert "TypeError" not in out.err and "real number" not in out.err


def test_the_generated_config_has_no_rust_doc_links(capsys):
    assert main(["config", "--default"]) == 0
    text = capsys.readouterr().out
    # a link is a bracketed code name ([`Name`], [`a::b`]); "in [`min_points`, 100000]" is
    # an interval
    assert "crate::" not in text and re.findall(r"\[`[^`\]]+`\]", text) == []
    # the link the issue found is now the Python class it raises
    assert "OutOfBoundsError" in text
