"""The dataset source's decode-ahead thread: same frames in the same order as decoding
inline, worker errors raised in the consumer, and an early stop ends the worker."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from floorscan.formats.dataset import read_images_txt
from floorscan.formats.image_io import read_grey
from floorscan.pipeline.sources import DatasetSource, _prefetched
from synthetic_dataset import make_dataset


def test_prefetched_frames_equal_inline_decoding(tmp_path):
    make_dataset(tmp_path / "ds", n=12)
    src = DatasetSource(tmp_path / "ds")
    frames = list(src)
    entries = read_images_txt(tmp_path / "ds")
    assert [f.index for f in frames] == list(range(len(entries)))
    for f, e in zip(frames, entries):
        assert f.timestamp == e.timestamp
        np.testing.assert_array_equal(f.image, read_grey(e.path))


def test_worker_errors_reach_the_consumer_after_the_frames_before_them():
    def frames():
        yield 1
        yield 2
        raise RuntimeError("disk on fire")

    got = []
    with pytest.raises(RuntimeError, match="disk on fire"):
        for x in _prefetched(frames(), 2):
            got.append(x)
    assert got == [1, 2]


def test_closing_early_stops_the_worker():
    produced = []

    def frames():
        for i in range(10_000):
            produced.append(i)
            yield i

    it = _prefetched(frames(), 4)
    assert [next(it) for _ in range(3)] == [0, 1, 2]
    it.close()
    assert not any(t.name == "floorscan-decode" and t.is_alive() for t in threading.enumerate())
    assert len(produced) <= 3 + 4 + 2  # bounded read-ahead
