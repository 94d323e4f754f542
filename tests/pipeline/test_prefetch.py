"""The dataset source's read-ahead (Rust threads decoding PNG files): the same frames in the
same order as decoding inline, unreadable frames in their place with read_grey's error, other
formats through Pillow, and closing the source early stops the threads."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from floorscan.formats.dataset import read_images_txt
from floorscan.formats.image_io import read_grey
from floorscan.pipeline.sources import DatasetSource
from hostile_corpus import png_claiming
from PIL import Image
from synthetic_dataset import make_dataset


def decoding_threads() -> int:
    """Threads of this process named by the read-ahead (Linux)."""
    tasks = Path("/proc/self/task")
    if not tasks.is_dir():
        return 0
    count = 0
    for t in tasks.iterdir():
        try:
            count += (t / "comm").read_text().startswith("floorscan-png")
        except OSError:  # a thread that exited while we looked
            pass
    return count


def decoding_threads_after_close() -> int:
    """The count once joined threads have left /proc: a thread's join returns when it has
    run to its end, and the kernel may list it for a moment longer (seen under load)."""
    for _ in range(100):
        if decoding_threads() == 0:
            return 0
        time.sleep(0.01)
    return decoding_threads()


def test_frames_equal_inline_decoding(tmp_path):
    make_dataset(tmp_path / "ds", n=12)
    src = DatasetSource(tmp_path / "ds")
    frames = list(src)
    inline = list(src._frames())
    entries = read_images_txt(tmp_path / "ds")
    assert [f.index for f in frames] == list(range(len(entries)))
    for f, g, e in zip(frames, inline, entries):
        assert f.timestamp == g.timestamp == e.timestamp
        np.testing.assert_array_equal(f.image, g.image)
        np.testing.assert_array_equal(f.image, read_grey(e.path))


def test_unreadable_frames_keep_their_place_and_read_greys_error(tmp_path):
    make_dataset(tmp_path / "ds", n=8)
    entries = read_images_txt(tmp_path / "ds")
    entries[2].path.write_bytes(png_claiming(40000, 40000))  # over max_image_pixels
    entries[3].path.write_bytes(entries[3].path.read_bytes()[:100])  # truncated
    entries[4].path.unlink()  # missing
    grey = read_grey(entries[5].path)
    Image.fromarray(grey).save(entries[5].path, format="BMP")  # not a PNG: Pillow reads it
    frames = list(DatasetSource(tmp_path / "ds"))
    assert [f.image is None for f in frames] == [False, False, True, True, True] + [False] * 3
    for k in (2, 3, 4):
        try:
            read_grey(entries[k].path)
        except Exception as e:  # noqa: BLE001 - the reference message
            assert frames[k].error == str(e)
    np.testing.assert_array_equal(frames[5].image, grey)


def test_closing_early_stops_the_decoding_threads(tmp_path):
    make_dataset(tmp_path / "ds", n=40)
    src = DatasetSource(tmp_path / "ds")
    it = iter(src)
    assert [next(it).index for _ in range(3)] == [0, 1, 2]
    assert decoding_threads() >= 1 or not Path("/proc/self/task").is_dir()
    src.close()
    assert decoding_threads_after_close() == 0
    assert [f.index for f in src] == list(range(40))  # a new iteration starts over
    assert decoding_threads_after_close() == 0
