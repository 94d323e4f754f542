"""Per-frame ranging time on a 640x480 uint8 image, boundary around mid-image, side by side in
one run, one thread: floorscan's scan through its Python API (FFI, checks, sub-pixel refinement
and ground lookup included) against the strongest versions a careful user would write:

- OpenCV over the whole image: a vertical filter (the paper's box filter as `cv2.filter2D`, or
  `cv2.Sobel`), then the first row above the threshold from the bottom, found on the sampled
  columns only;
- numpy on the sampled columns only: the paper's box filter of eq. (1) by a cumulative sum
  along the rows of `img[rows, cols]`, restricted to the rows that can hold ground within the
  ranger's 3 m limit, then the first crossing from the bottom.

The baselines find the first-crossing row only (no refinement, no ground lookup); the script
checks that numpy's rows equal floorscan's with first-crossing refinement on every column.

Run: .venv/bin/python bench/ranging_vs_opencv.py  (prints a Markdown table)
"""

from __future__ import annotations

import platform
import time

import cv2
import floorscan
import numpy as np

W, H, D, T = 640, 480, 4, 12.0
MARGIN = 2  # the ranger's default bottom margin
TOP_ROW = 200  # no ground within 3 m above this row in the table below


def frame(seed: int = 7) -> np.ndarray:
    rng = np.random.default_rng(seed)
    v, u = np.mgrid[0:H, 0:W]
    boundary = 240 + 20 * np.sin(u / 50.0)
    img = np.where(v < boundary, 170, 90) + rng.integers(-4, 5, size=(H, W))
    return img.astype(np.uint8)


def table() -> floorscan.GroundTable:
    def ground(u, v):
        x = 0.3 + (H - v) * 0.01
        return np.where(v > 20, x, np.nan), (W / 2 - u) * 0.004

    return floorscan.GroundTable.from_function(ground, image_width=W, image_height=H, spacing_px=8)


def first_from_bottom(above: np.ndarray) -> np.ndarray:
    """Row of the lowest True per column (-1 if none)."""
    flipped = above[::-1]
    idx = flipped.argmax(axis=0)
    return np.where(flipped.any(axis=0), above.shape[0] - 1 - idx, -1)


def opencv_box(img: np.ndarray, cols: np.ndarray) -> np.ndarray:
    kernel = np.zeros((2 * D + 1, 1), np.float32)
    kernel[:D] = 1.0 / (2 * D)  # above (smaller v)
    kernel[D + 1 :] = -1.0 / (2 * D)  # below
    response = cv2.filter2D(img, cv2.CV_32F, kernel, borderType=cv2.BORDER_REPLICATE)
    return first_from_bottom(np.abs(response[:, cols]) > T)


def opencv_sobel(img: np.ndarray, cols: np.ndarray) -> np.ndarray:
    gy = cv2.Sobel(img, cv2.CV_16S, 0, 1, ksize=3)
    return first_from_bottom(np.abs(gy[:, cols]) > 8 * T)


def numpy_columns(img: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Eq. (1) on the sampled columns only, rows TOP_ROW - D .. H - 1 - MARGIN, by cumsum."""
    sub = img[TOP_ROW - D : H - MARGIN, cols][::-1]  # k = 0 is the start row
    c = np.zeros((sub.shape[0] + 1, sub.shape[1]), np.int32)
    np.cumsum(sub, axis=0, dtype=np.int32, out=c[1:])
    k = np.arange(D, sub.shape[0] - D)
    s = (c[k + D + 1] - c[k + 1]) - (c[k] - c[k - D])
    hit = np.abs(s) > int(np.floor(2 * D * T))
    first = hit.argmax(axis=0)
    return np.where(hit.any(axis=0), H - 1 - MARGIN - (first + D), -1)


def per_frame_us(fn, repeat: int) -> float:
    fn()
    best = float("inf")
    for _ in range(7):
        t0 = time.perf_counter()
        for _ in range(repeat):
            fn()
        best = min(best, (time.perf_counter() - t0) / repeat)
    return best * 1e6


def check_numpy_matches(img: np.ndarray, tab: floorscan.GroundTable) -> float:
    """Fraction of the 640 columns where numpy's first crossing agrees with floorscan's
    (first-crossing refinement): the same row where floorscan finds a boundary, and no crossing
    below floorscan's top row (its 3 m limit) where it finds none."""
    ranger = floorscan.VisualRanger(
        tab, columns=W, half_width_px=D, threshold=T, refinement="first_crossing"
    )
    scan = ranger.scan(img)
    theirs = numpy_columns(img, ranger.columns.astype(np.intp))
    status, rows = scan.status, scan.rows
    same = np.where(
        status == "boundary",
        theirs == np.round(rows),
        (status == "no_boundary") & ((theirs < rows) | (theirs == -1)),
    )
    return float(np.mean(same))


def main() -> None:
    img = frame()
    tab = table()
    rows = []
    for n in (32, 64, 640):
        ranger = floorscan.VisualRanger(tab, columns=n, half_width_px=D, threshold=T)
        cols = ranger.columns.astype(np.intp)
        ours = per_frame_us(lambda r=ranger: r.scan(img), 2000 if n < 640 else 500)
        box = per_frame_us(lambda c=cols: opencv_box(img, c), 100)
        sobel = per_frame_us(lambda c=cols: opencv_sobel(img, c), 100)
        npcol = per_frame_us(lambda c=cols: numpy_columns(img, c), 200)
        rows.append((n, ours, box, sobel, npcol))
    total = per_frame_us(lambda: int(img.sum(dtype=np.uint64)), 200)
    agree = check_numpy_matches(img, tab)
    print(
        f"Machine: {platform.processor() or platform.machine()}, one thread (cv2.setNumThreads(1)).\n"
    )
    print(
        "| columns | floorscan (Python API) | OpenCV filter2D box, whole image | OpenCV Sobel, whole image "
        "| numpy eq. (1) on the sampled columns | strongest baseline | floorscan speed-up |"
    )
    print("|---:|---:|---:|---:|---:|---|---:|")
    names = ("OpenCV box", "OpenCV Sobel", "numpy columns")
    for n, ours, box, sobel, npcol in rows:
        times = (box, sobel, npcol)
        best = min(times)
        print(
            f"| {n} | {ours:.1f} us | {box:.0f} us | {sobel:.0f} us | {npcol:.0f} us "
            f"| {names[times.index(best)]} | {best / ours:.1f}x |"
        )
    print(f"\nnumpy sum over all pixels (one read of the image): {total:.0f} us")
    print(
        f"numpy's first-crossing rows equal floorscan's on {100 * agree:.1f} % of the 640 columns"
    )


if __name__ == "__main__":
    cv2.setNumThreads(1)
    main()
