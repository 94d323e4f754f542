"""floorscan.formats.gif (GIF frames encoded on a Rust thread): what Pillow reads back is what
was written (indices, palette, delay, loop), the file appears only when complete, an abort
leaves nothing, and bad frames or unwritable paths are one-line errors."""

from __future__ import annotations

import numpy as np
import pytest
from floorscan.errors import ImageError, OutputError
from floorscan.formats.gif import GifWriter
from PIL import Image, ImageSequence

RNG = np.random.default_rng(7)
PALETTE = RNG.integers(0, 256, size=(256, 3), dtype=np.uint8)


def frames(n: int, h: int = 30, w: int = 41):
    return [RNG.integers(0, 256, size=(h, w), dtype=np.uint8) for _ in range(n)]


def test_pillow_reads_back_the_indices_palette_and_timing(tmp_path):
    path = tmp_path / "a.gif"
    sent = frames(5)
    gif = GifWriter(path, width=41, height=30, palette=PALETTE, frame_s=0.1)
    for f in sent:
        gif.add(f)
    assert gif.close() == path
    with Image.open(path) as im:
        assert im.n_frames == 5 and im.info["loop"] == 0
        for f, got in zip(sent, ImageSequence.Iterator(im)):
            assert got.info["duration"] == 100
            rgb = np.asarray(got.convert("RGB"))
            np.testing.assert_array_equal(rgb, PALETTE[f])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.gif"]


def test_the_file_appears_only_when_complete_and_abort_leaves_nothing(tmp_path):
    path = tmp_path / "a.gif"
    gif = GifWriter(path, width=41, height=30, palette=PALETTE, frame_s=0.1)
    gif.add(frames(1)[0])
    assert not path.exists()
    gif.abort()
    gif.abort()
    assert list(tmp_path.iterdir()) == []


def test_bad_frames_and_palettes_are_image_errors(tmp_path):
    gif = GifWriter(tmp_path / "a.gif", width=4, height=3, palette=PALETTE, frame_s=0.1)
    for bad in (np.zeros((4, 3), np.uint8), np.zeros((3, 4), np.uint16), [[0] * 4] * 3):
        with pytest.raises(ImageError, match="GIF frame must be"):
            gif.add(bad)
    gif.abort()
    for bad in (np.zeros((300, 3), np.uint8), np.zeros((4, 4), np.uint8), np.zeros((0, 3))):
        with pytest.raises(ImageError) as e:
            GifWriter(tmp_path / "b.gif", width=4, height=3, palette=bad, frame_s=0.1)
        assert "\n" not in str(e.value)
    with pytest.raises(ImageError, match="width must be 1..=65535"):
        GifWriter(tmp_path / "b.gif", width=0, height=3, palette=PALETTE, frame_s=0.1)
    assert list(tmp_path.iterdir()) == []


def test_an_unwritable_path_is_an_output_error(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError):
        GifWriter(tmp_path / "file" / "a.gif", width=4, height=3, palette=PALETTE, frame_s=0.1)
