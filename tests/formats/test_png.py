"""floorscan.formats.png (the Rust PNG decoder) against Pillow's pixels for every kind of PNG
Pillow writes (grey, grey + alpha, RGB, RGBA, palette with and without transparency, 1/2/4/8/16
bits, interlaced), and hostile files: truncated, corrupt, huge declared sizes, foreign bytes."""

from __future__ import annotations

import io
import struct
import zlib

import numpy as np
import pytest
from floorscan.errors import FloorscanError, ImageError, ImageTooLargeError
from floorscan.formats import image_io
from floorscan.formats.png import is_png, png_to_array, png_to_grey
from hostile_corpus import png_claiming
from PIL import Image

LIMIT = 1 << 26
RNG = np.random.default_rng(14)


def png_bytes(im: Image.Image, **save) -> bytes:
    buf = io.BytesIO()
    im.save(buf, format="PNG", **save)
    return buf.getvalue()


def pillow_grey(data: bytes) -> np.ndarray:
    """What read_grey returned before the Rust decoder: Pillow's pixels."""
    with Image.open(io.BytesIO(data)) as im:
        im.load()
        if im.mode in ("I;16", "I;16B", "I;16L", "I"):
            return np.asarray(im).astype(np.uint16)
        return np.asarray(im.convert("L"))


def noise(shape, dtype=np.uint8, high=256) -> np.ndarray:
    return RNG.integers(0, high, size=shape, dtype=np.int64).astype(dtype)


def chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def raw_png(w: int, h: int, bit_depth: int, colour_type: int, rows: bytes, **extra) -> bytes:
    """A PNG written by hand (filter 0 on every row): types Pillow does not write itself."""
    ihdr = struct.pack(">IIBBBBB", w, h, bit_depth, colour_type, 0, 0, extra.get("interlace", 0))
    body = chunk(b"IHDR", ihdr)
    for kind, data in extra.get("chunks", []):
        body += chunk(kind, data)
    return b"\x89PNG\r\n\x1a\n" + body + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")


CASES = {
    "grey8": lambda: Image.fromarray(noise((37, 53))),
    "grey16": lambda: Image.fromarray(noise((21, 19), np.uint16, 65536)),
    "grey_alpha": lambda: Image.fromarray(noise((17, 23, 2)), "LA"),
    "rgb": lambda: Image.fromarray(noise((29, 31, 3))),
    "rgba": lambda: Image.fromarray(noise((13, 11, 4))),
    "palette": lambda: Image.fromarray(noise((25, 27, 3))).quantize(200),
    "palette_16_colours": lambda: Image.fromarray(noise((25, 27, 3))).quantize(16),
    "palette_transparent": lambda: Image.fromarray(noise((25, 27, 3))).quantize(50),
    "bilevel": lambda: Image.fromarray(noise((19, 45)) > 128),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_grey_pixels_equal_pillows(name):
    save = {"transparency": 3} if name == "palette_transparent" else {}
    data = png_bytes(CASES[name](), **save)
    got = png_to_grey(data, max_pixels=LIMIT)
    want = pillow_grey(data)
    assert got.dtype == want.dtype and got.shape == want.shape
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("name", ["grey8", "grey_alpha", "rgb", "rgba", "palette", "bilevel"])
def test_pixels_as_stored_equal_pillows(name):
    data = png_bytes(CASES[name]())
    with Image.open(io.BytesIO(data)) as im:
        mode = {"P": "RGB", "1": "L"}.get(im.mode, im.mode)
        want = np.asarray(im.convert(mode))
    np.testing.assert_array_equal(png_to_array(data, max_pixels=LIMIT), want)


ADAM7 = [
    (0, 0, 8, 8),
    (4, 0, 8, 8),
    (0, 4, 4, 8),
    (2, 0, 4, 4),
    (0, 2, 2, 4),
    (1, 0, 2, 2),
    (0, 1, 1, 2),
]
"""The seven passes of Adam7 interlacing: (x0, y0, dx, dy)."""


def adam7_rows(img: np.ndarray) -> bytes:
    """Image data of an 8-bit (H, W) or (H, W, C) image, interlaced (Pillow cannot write it)."""
    out = b""
    for x0, y0, dx, dy in ADAM7:
        sub = img[y0::dy, x0::dx]
        if sub.shape[0] and sub.shape[1]:
            out += b"".join(b"\x00" + row.tobytes() for row in sub)
    return out


@pytest.mark.parametrize(
    "channels, colour_type", [(1, 0), (2, 4), (3, 2), (4, 6)], ids=["grey", "la", "rgb", "rgba"]
)
def test_interlaced_pixels_equal_pillows(channels, colour_type):
    h, w = 37, 29  # not multiples of 8: partial passes
    img = noise((h, w, channels))[..., 0] if channels == 1 else noise((h, w, channels))
    data = raw_png(w, h, 8, colour_type, adam7_rows(img), interlace=1)
    np.testing.assert_array_equal(png_to_grey(data, max_pixels=LIMIT), pillow_grey(data))
    np.testing.assert_array_equal(png_to_array(data, max_pixels=LIMIT), img)


@pytest.mark.parametrize("bits", [1, 2, 4])
def test_low_bit_grey_is_scaled_as_pillow_scales_it(bits):
    w, h = 13, 7
    values = noise((h, w), high=1 << bits)
    per_byte = 8 // bits
    rows = b""
    for row in values:
        padded = np.concatenate([row, np.zeros(-w % per_byte, np.uint8)])
        packed = bytearray()
        for k in range(0, len(padded), per_byte):
            byte = 0
            for v in padded[k : k + per_byte]:
                byte = (byte << bits) | int(v)
            packed.append(byte)
        rows += b"\x00" + bytes(packed)
    data = raw_png(w, h, bits, 0, rows)
    got = png_to_grey(data, max_pixels=LIMIT)
    np.testing.assert_array_equal(got, pillow_grey(data))
    np.testing.assert_array_equal(got, values * (255 // ((1 << bits) - 1)))


def test_sixteen_bit_rgb_keeps_the_high_byte_as_pillow_does():
    w, h = 5, 4
    values = noise((h, w, 3), np.uint16, 65536)
    rows = b"".join(b"\x00" + row.astype(">u2").tobytes() for row in values)
    data = raw_png(w, h, 16, 2, rows)
    np.testing.assert_array_equal(png_to_grey(data, max_pixels=LIMIT), pillow_grey(data))
    np.testing.assert_array_equal(png_to_array(data, max_pixels=LIMIT), values >> 8)


def test_read_grey_gives_pillows_pixels_for_png_and_uses_pillow_for_the_rest(tmp_path):
    img = noise((48, 64))
    Image.fromarray(img).save(tmp_path / "a.png")
    Image.fromarray(img).save(tmp_path / "a.bmp")
    np.testing.assert_array_equal(image_io.read_grey(tmp_path / "a.png"), img)
    np.testing.assert_array_equal(image_io.read_grey(tmp_path / "a.bmp"), img)
    assert is_png((tmp_path / "a.png").read_bytes())
    assert not is_png((tmp_path / "a.bmp").read_bytes())


def test_returns_writable_arrays_of_the_header_size():
    a = png_to_grey(png_bytes(Image.fromarray(noise((3, 5)))), max_pixels=15)
    assert a.shape == (3, 5) and a.flags.c_contiguous and a.flags.writeable


def one_line_image_error(data: bytes, cls=ImageError, max_pixels=LIMIT) -> str:
    with pytest.raises(cls) as e:
        png_to_grey(data, max_pixels=max_pixels)
    msg = str(e.value)
    assert isinstance(e.value, FloorscanError) and isinstance(e.value, ValueError)
    assert "\n" not in msg and msg
    return msg


def test_truncated_corrupt_and_foreign_bytes_are_one_line_image_errors():
    good = png_bytes(Image.fromarray(noise((40, 40))))
    for bad in (good[:-30], good[: len(good) // 2], good[:33], good[:8], b"", b"GIF89a" + good):
        one_line_image_error(bad)
    corrupt = bytearray(good)
    corrupt[60] ^= 0xFF  # inside IDAT: the chunk CRC no longer matches
    one_line_image_error(bytes(corrupt))


def test_huge_declared_dimensions_are_refused_on_the_header():
    msg = one_line_image_error(png_claiming(40000, 40000), ImageTooLargeError)
    assert "40000 x 40000" in msg and str(LIMIT) in msg
    one_line_image_error(png_claiming(0x7FFFFFFF, 0x7FFFFFFF), ImageTooLargeError)
    # Within a raised limit the header passes, and the one-row IDAT is a truncated image.
    one_line_image_error(png_claiming(40000, 40000), ImageError, max_pixels=1 << 40)


def test_wrong_bit_depths_and_colour_types_are_image_errors():
    for depth, colour in [(3, 0), (8, 1), (16, 3), (4, 2), (7, 6), (32, 0)]:
        one_line_image_error(raw_png(2, 2, depth, colour, b"\x00" * 40))


def test_read_grey_respects_set_max_image_pixels(tmp_path):
    path = tmp_path / "big.png"
    Image.fromarray(noise((100, 100))).save(path)
    try:
        image_io.set_max_image_pixels(9999)
        with pytest.raises(ImageTooLargeError, match=r"100 x 100 .*max_image_pixels"):
            image_io.read_grey(path)
        image_io.set_max_image_pixels(10000)
        assert image_io.read_grey(path).shape == (100, 100)
    finally:
        image_io.set_max_image_pixels(image_io.DEFAULT_MAX_IMAGE_PIXELS)
    path.write_bytes(path.read_bytes()[:200])
    with pytest.raises(ImageError, match=f"cannot read image {path}"):
        image_io.read_grey(path)
