"""floorscan.ranging.overlay: the palette-indexed overlay (what `run` streams into its GIF) is
the RGB overlay with greys rounded to the palette's 252 levels: the same marks in the same
places and colours."""

from __future__ import annotations

import numpy as np
from floorscan.ranging.overlay import (
    OVERLAY_PALETTE,
    STATUS_COLOURS,
    draw_scan_overlay,
    draw_scan_overlay_indexed,
)
from synthetic_dataset import camera_table, make_dataset


def test_indexed_overlay_is_the_rgb_overlay_with_greys_on_the_palette(tmp_path):
    from floorscan import VisualRanger
    from floorscan.formats.image_io import read_grey

    make_dataset(tmp_path / "room", n=2)
    image = read_grey(sorted((tmp_path / "room" / "images").iterdir())[0])
    scan = VisualRanger(camera_table(), threshold=20).scan(image, timestamp=0.0)
    rgb = draw_scan_overlay(image, scan)
    indexed = draw_scan_overlay_indexed(image, scan)
    assert indexed.shape == image.shape and indexed.dtype == np.uint8
    marks = indexed >= 252
    assert marks.any()
    # Marked pixels: the RGB overlay's colour; the others: its grey within half a palette step.
    np.testing.assert_array_equal(OVERLAY_PALETTE[indexed[marks]], rgb[marks])
    plain = ~marks
    diff = np.abs(OVERLAY_PALETTE[indexed[plain], 0].astype(int) - rgb[plain][:, 0].astype(int))
    assert diff.max() <= 1
    coloured = ~np.all(rgb == rgb[..., :1], axis=-1)  # every non-grey pixel is a mark
    assert coloured.any() and marks[coloured].all()


def test_palette_holds_the_greys_then_the_status_colours():
    assert OVERLAY_PALETTE.shape == (256, 3) and OVERLAY_PALETTE.dtype == np.uint8
    assert tuple(OVERLAY_PALETTE[0]) == (0, 0, 0) and tuple(OVERLAY_PALETTE[251]) == (255,) * 3
    assert np.all(np.diff(OVERLAY_PALETTE[:252, 0].astype(int)) > 0)
    assert [tuple(c) for c in OVERLAY_PALETTE[252:]] == list(STATUS_COLOURS.values())


def test_a_wide_image_is_halved_before_the_marks_are_drawn(tmp_path):
    from floorscan import VisualRanger
    from floorscan.formats.image_io import read_grey

    make_dataset(tmp_path / "room", n=2)
    image = read_grey(sorted((tmp_path / "room" / "images").iterdir())[0])
    scan = VisualRanger(camera_table(), threshold=20).scan(image, timestamp=0.0)
    h, w = image.shape
    small = draw_scan_overlay_indexed(image, scan, max_width=w - 1)
    assert small.shape == image[::2, ::2].shape
    full = draw_scan_overlay_indexed(image, scan)
    plain = (small < 252) & (full[::2, ::2] < 252)
    np.testing.assert_array_equal(small[plain], full[::2, ::2][plain])  # the same greys
    # Each boundary mark sits at half the column and row of the full-size one.
    boundary = np.asarray(scan.status) == "boundary"
    for u, v in zip(scan.columns[boundary], scan.rows[boundary]):
        r, c = int(round(v / 2)), int(u) // 2
        near = small[max(r - 4, 0) : r + 5, max(c - 4, 0) : c + 5]
        assert (near == 252).any()
    assert np.array_equal(draw_scan_overlay_indexed(image, scan, max_width=w), full)
