"""`floorscan tune`'s plot: a PNG of the asked size, written atomically, whatever the curves."""

import numpy as np
from floorscan.evaluation.plot import plot_curves
from PIL import Image


def test_plot_is_a_png_of_the_asked_size(tmp_path):
    out = plot_curves(
        tmp_path / "p.png",
        [2, 4, 6, 8],
        {"d = 2": [0.3, 0.2, float("nan"), 0.1], "d = 4": [0.4, 0.1, 0.05, 0.1]},
        title="error vs threshold",
        x_label="threshold",
        y_label="share wrong",
        marker=(6, 0.05, "chosen"),
        vline=(5, "auto"),
        size=(640, 400),
    )
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size == (640, 400)
        pixels = np.asarray(im.convert("RGB"))
    assert pixels.std() > 10  # lines drawn, not a blank canvas
    assert [p.name for p in tmp_path.iterdir()] == ["p.png"]  # no temporary file left
