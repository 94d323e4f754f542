"""Per-frame ranging time on a 640x480 uint8 image, boundary around mid-image, side by side in
one run: floorscan's incremental scan (through the Python API, so FFI included), and what a user
would write with OpenCV or numpy: a vertical edge filter over the whole image, then the first
row from the bottom above the threshold in each column.

Run: .venv/bin/python bench/ranging_vs_opencv.py  (prints a Markdown table)
"""

from __future__ import annotations

import platform
import time

import cv2
import floorscan
import numpy as np

W, H, D, T = 640, 480, 4, 12.0


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
    return np.where(flipped.any(axis=0), H - 1 - idx, -1)


def opencv_box(img: np.ndarray, cols: np.ndarray) -> np.ndarray:
    kernel = np.zeros((2 * D + 1, 1), np.float32)
    kernel[:D] = 1.0 / (2 * D)  # above (smaller v)
    kernel[D + 1 :] = -1.0 / (2 * D)  # below
    response = cv2.filter2D(img, cv2.CV_32F, kernel, borderType=cv2.BORDER_REPLICATE)
    return first_from_bottom(np.abs(response) > T)[cols]


def opencv_sobel(img: np.ndarray, cols: np.ndarray) -> np.ndarray:
    gy = cv2.Sobel(img, cv2.CV_16S, 0, 1, ksize=3)
    return first_from_bottom(np.abs(gy) > 8 * T)[cols]


def numpy_box(img: np.ndarray, cols: np.ndarray) -> np.ndarray:
    c = np.zeros((H + 1, W), np.int32)
    np.cumsum(img, axis=0, dtype=np.int32, out=c[1:])
    n = np.arange(D, H - D)
    above = c[n] - c[n - D]  # rows n-D .. n-1
    below = c[n + D + 1] - c[n + 1]  # rows n+1 .. n+D
    hit = np.zeros((H, W), bool)
    hit[D : H - D] = np.abs(above - below) > 2 * D * T
    return first_from_bottom(hit)[cols]


def per_frame_us(fn, repeat: int) -> float:
    fn()
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(repeat):
            fn()
        best = min(best, (time.perf_counter() - t0) / repeat)
    return best * 1e6


def main() -> None:
    img = frame()
    tab = table()
    rows = []
    for n in (32, 64, 640):
        ranger = floorscan.VisualRanger(tab, columns=n, half_width_px=D, threshold=T)
        cols = ranger.columns.astype(np.intp)
        ours = per_frame_us(lambda r=ranger: r.scan(img), 2000 if n < 640 else 500)
        box = per_frame_us(lambda c=cols: opencv_box(img, c), 50)
        sobel = per_frame_us(lambda c=cols: opencv_sobel(img, c), 50)
        npbox = per_frame_us(lambda c=cols: numpy_box(img, c), 20)
        rows.append((n, ours, box, sobel, npbox))
    total = per_frame_us(lambda: int(img.sum(dtype=np.uint64)), 200)
    print(
        f"Machine: {platform.processor() or platform.machine()}, one thread (cv2.setNumThreads(1)).\n"
    )
    print(
        "| columns | floorscan (Python API) | OpenCV box filter2D | OpenCV Sobel | numpy cumsum box | speed-up vs best OpenCV/numpy |"
    )
    print("|---:|---:|---:|---:|---:|---:|")
    for n, ours, box, sobel, npbox in rows:
        best = min(box, sobel, npbox)
        print(
            f"| {n} | {ours:.1f} us | {box:.0f} us | {sobel:.0f} us | {npbox:.0f} us | {best / ours:.0f}x |"
        )
    print(f"\nnumpy sum over all pixels (read the image once): {total:.0f} us")


if __name__ == "__main__":
    cv2.setNumThreads(1)
    main()
