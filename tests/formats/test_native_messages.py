"""What native code writes on file descriptor 2 is caught inside native_messages() and given
back as lines; what is written before and after still reaches stderr."""

from __future__ import annotations

import os
import sys

import pytest
from floorscan.errors import DatasetError, ImageError
from floorscan.formats.dataset import read_images_txt
from floorscan.formats.image_io import read_grey
from floorscan.formats.native_messages import MAX_MESSAGE_BYTES, native_messages
from floorscan.pipeline.sources import VideoSource


def test_lines_written_to_the_descriptor_are_caught(capfd):
    os.write(2, b"before\n")
    with native_messages() as said:
        os.write(2, b"[mjpeg @ 0x1] huffman table decode error\n\n  second line  \n")
    os.write(2, b"after\n")
    assert said.lines == ["[mjpeg @ 0x1] huffman table decode error", "second line"]
    assert said.first == "[mjpeg @ 0x1] huffman table decode error" and said
    assert capfd.readouterr().err == "before\nafter\n"


def test_nothing_written_is_nothing_caught(capfd):
    with native_messages() as said:
        pass
    assert not said and said.first == "" and said.lines == []
    sys.stderr.write("ours\n")
    assert capfd.readouterr().err == "ours\n"


def test_a_flood_is_kept_to_its_bound():
    with native_messages() as said:
        os.write(2, b"x" * (3 * MAX_MESSAGE_BYTES) + b"\n")
    assert sum(len(line) for line in said.lines) <= MAX_MESSAGE_BYTES


def test_the_descriptor_comes_back_after_an_exception(capfd):
    with pytest.raises(RuntimeError):
        with native_messages():
            raise RuntimeError("inside")
    os.write(2, b"still here\n")
    assert capfd.readouterr().err == "still here\n"


def test_a_damaged_video_says_why_in_its_one_line(tmp_path, capfd):
    bad = tmp_path / "v.avi"
    bad.write_bytes(b"RIFF\x10\x00\x00\x00AVI LIST" + bytes(64))
    capfd.readouterr()
    with pytest.raises(DatasetError, match=r"cannot open video .*\(Unexpected list type"):
        VideoSource(bad)  # OpenCV's AVI parser prints why: it comes in the error, not raw
    assert capfd.readouterr().err == ""


def test_a_path_with_a_nul_byte_is_an_error_not_a_crash(tmp_path):
    with pytest.raises(ImageError, match="NUL"):
        read_grey(str(tmp_path / "a\x00b.png"))
    (tmp_path / "images.txt").write_text("1.0 images/a\x00.png\n")
    with pytest.raises(DatasetError, match="NUL"):
        read_images_txt(tmp_path)
