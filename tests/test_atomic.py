"""Atomic writes leave the target readable like a normal file and no temporary behind."""

from __future__ import annotations

import os
import stat

import pytest
from floorscan._atomic import write_atomic


def test_atomic_write_has_normal_permissions(tmp_path):
    mask = os.umask(0o022)
    try:
        p = write_atomic(tmp_path / "map.yaml", "image: map.pgm\n")
    finally:
        os.umask(mask)
    assert stat.S_IMODE(p.stat().st_mode) == 0o644
    assert [q.name for q in tmp_path.iterdir()] == ["map.yaml"]


def test_failed_write_keeps_the_old_file(tmp_path):
    p = write_atomic(tmp_path / "a.txt", "old")

    def boom(f):
        f.write(b"partial")
        raise RuntimeError("disk full")

    from floorscan._atomic import write_atomic_with

    with pytest.raises(RuntimeError):
        write_atomic_with(p, boom)
    assert p.read_text() == "old"
    assert [q.name for q in tmp_path.iterdir()] == ["a.txt"]
