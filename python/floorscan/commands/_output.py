"""The command line's one output grammar: every command that writes takes ``-o/--output`` and
``--force``, and nothing it would write is overwritten without ``--force``.

A command declares its outputs with :func:`add_output` (and :func:`also_writes` for optional
extra outputs such as ``--png``); ``floorscan.cli`` calls :func:`refuse_overwrites` on the
parsed arguments before the command runs, so a long job never fails at its end on a file that
was there before it started.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, Dict, Iterable, Optional, Tuple

from ..errors import OptionError, OutputError

FILE = "file"
"""An output that is one file: refused when anything exists at its path."""
FOLDER = "folder"
"""An output that is a folder of files: refused when it exists and is not empty."""


def add_output(
    p: argparse.ArgumentParser,
    kind: str,
    help: str,
    *,
    default: Optional[str] = None,
    required: bool = True,
    aliases: tuple = (),
) -> None:
    """``-o/--output`` (required unless ``default`` is given or ``required`` is False) and
    ``--force``. ``aliases`` are older spellings (``--out``) that still work but are not shown
    in the help."""
    # the old spellings share a required group with -o/--output: either one satisfies it
    group = p.add_mutually_exclusive_group(required=required and default is None)
    if default is None:
        group.add_argument("-o", "--output", help=help)
    else:
        group.add_argument("-o", "--output", default=default, help=f"{help} (default %(default)s)")
    for alias in aliases:
        group.add_argument(alias, dest="output", help=argparse.SUPPRESS)
    p.add_argument(
        "--force",
        action="store_true",
        help=f"overwrite the output {'file' if kind == FILE else 'folder'} if it exists",
    )
    _outputs(p)["output"] = kind


def also_writes(p: argparse.ArgumentParser, dest: str, kind: str = FILE) -> None:
    """Declares one more output, the path of the option stored in ``dest`` (e.g. ``--png``)."""
    _outputs(p)[dest] = kind


def _outputs(p: argparse.ArgumentParser) -> Dict[str, str]:
    outputs = p.get_default("outputs")
    if outputs is None:
        outputs = {}
        p.set_defaults(outputs=outputs)
    return outputs


def refuse_overwrites(args: argparse.Namespace) -> None:
    """OptionError naming the first declared output that exists (a file, or a folder that is
    not empty), unless ``--force`` was given."""
    outputs: Dict[str, str] = getattr(args, "outputs", None) or {}
    paths = [(getattr(args, dest, None), kind) for dest, kind in outputs.items()]
    refuse_existing(paths, force=getattr(args, "force", False))


def refuse_existing(paths: Iterable[Tuple[Any, str]], *, force: bool) -> None:
    """OptionError naming the first of ``(path, FILE | FOLDER)`` that exists (None paths are
    skipped), unless ``force``; OutputError for a file that is a folder or a folder that is a
    file, forced or not. Also for outputs a command derives from ``-o`` (files beside it)."""
    for value, kind in paths:
        if value is None:
            continue
        path = Path(value)
        if kind == FOLDER and path.exists() and not path.is_dir():
            raise OutputError(f"output folder {path} exists and is not a folder")
        if kind == FILE and path.is_dir():
            raise OutputError(f"output file {path} is a folder")
        if force:
            continue
        if kind == FOLDER and path.is_dir():
            if any(path.iterdir()):
                raise OptionError(
                    f"{path} exists and is not empty: pass --force to overwrite its files"
                )
        elif path.exists():
            raise OptionError(f"{path} exists: pass --force to overwrite it")
