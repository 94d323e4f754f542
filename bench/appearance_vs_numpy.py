"""Side-by-side: floorscan's appearance ranger against the same method written with numpy
(whole-image vectorised: tests/appearance_reference.py, the brute-force reference of the
tests, the form a careful numpy user would write), on the frame of the criterion bench
(640x480 RGB, tiled floor, wall above row ~240), 64 and 640 columns. Both compute the same
readings (checked here). Times are medians of 30 runs on one core.

Run: `.venv/bin/python bench/appearance_vs_numpy.py`
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import floorscan as fs  # noqa: E402
from appearance_reference import appearance_scan  # noqa: E402
from floorscan.evaluation.floor_masks import image_row_table  # noqa: E402

W, H = 640, 480


def frame() -> np.ndarray:
    rng = np.random.default_rng(7)
    v, u = np.mgrid[0:H, 0:W]
    img = np.where(((u // 40 + v // 40) % 2 == 0)[..., None], [150, 135, 115], [175, 160, 140])
    img = np.where(((u % 40 < 2) | (v % 40 < 2))[..., None], [90, 90, 88], img)
    boundary = 240 + 20 * np.sin(u / 50.0)
    img = np.where((v < boundary)[..., None], [60, 90, 170], img)
    return np.clip(img + rng.integers(-4, 5, img.shape), 0, 255).astype(np.uint8)


def median_ms(f, n=30) -> float:
    f()
    t = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return 1000 * float(np.median(t))


def main() -> None:
    img = frame()
    print("| columns | floorscan [ms] | numpy [ms] | ratio |")
    print("|---:|---:|---:|---:|")
    for n in (64, 640):
        r = fs.AppearanceRanger(
            image_row_table(W, H), columns=n, start={"bottom_margin": 0}, max_range_m=None
        )
        cols = r.columns.astype(np.int64)
        s = r.scan(img)
        status, rows = appearance_scan(img, cols, start_row=H - 1)
        assert np.array_equal(s.status_codes, status) and np.array_equal(s.rows, rows)
        a = median_ms(lambda r=r: r.scan(img))
        b = median_ms(lambda cols=cols: appearance_scan(img, cols, start_row=H - 1))
        print(f"| {n} | {a:.2f} | {b:.2f} | {b / a:.1f}x |")


if __name__ == "__main__":
    main()
