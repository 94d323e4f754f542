"""Per-frame decode time of a 640x480 8-bit grey PNG, as `floorscan run` reads recorded frames,
side by side in one run, one thread: floorscan's Rust decoder (`formats.image_io.read_grey`,
and `formats.png.png_to_grey` on bytes already read), Pillow (what `read_grey` used before),
OpenCV's `cv2.imread` and `cv2.imdecode` (from bytes already read) with IMREAD_UNCHANGED, and
the file read alone (the disk / page-cache floor). The frame is a simulated corridor frame
written the way datasets are (Pillow's default PNG settings). Each decoder's output is checked
equal to Pillow's.

Run: .venv/bin/python bench/decode_candidates.py  (prints a Markdown table)
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import cv2
import numpy as np
from floorscan.formats.image_io import read_grey
from floorscan.formats.png import png_to_grey
from floorscan.sim import Camera, World, simulate_run
from PIL import Image


def per_frame_ms(fn, repeat: int = 50) -> float:
    fn()
    best = float("inf")
    for _ in range(7):
        t0 = time.perf_counter()
        for _ in range(repeat):
            fn()
        best = min(best, (time.perf_counter() - t0) / repeat)
    return best * 1e3


def main() -> None:
    sim = simulate_run(
        World.builtin("corridor"),
        camera=Camera(width=640, height=480),
        seconds=0.5,
        seed=3,
        threads=1,
        labels=False,
        truth=False,
    )
    img = np.ascontiguousarray(sim.images[len(sim) // 2])
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "frame.png"
        Image.fromarray(img).save(path, format="PNG")
        data = path.read_bytes()

        def pillow():
            with Image.open(path) as im:
                im.load()
                return np.asarray(im.convert("L"))

        def cv_imread():
            return cv2.imread(str(path), cv2.IMREAD_UNCHANGED)

        def cv_imdecode():
            buf = np.frombuffer(path.read_bytes(), np.uint8)
            return cv2.imdecode(buf, cv2.IMREAD_UNCHANGED)

        def rust_read_grey():
            return read_grey(path)

        def rust_png_to_grey():
            return png_to_grey(path.read_bytes(), max_pixels=1 << 26)

        for fn in (pillow, cv_imread, cv_imdecode, rust_read_grey, rust_png_to_grey):
            assert np.array_equal(fn(), img), fn.__name__
        rows = [
            ("file read only (path.read_bytes)", per_frame_ms(path.read_bytes, 500)),
            ("Pillow open + load + asarray (before)", per_frame_ms(pillow)),
            ("floorscan read_grey (Rust `png` crate, GIL released)", per_frame_ms(rust_read_grey)),
            ("read_bytes + floorscan png_to_grey", per_frame_ms(rust_png_to_grey)),
            ("OpenCV cv2.imread IMREAD_UNCHANGED", per_frame_ms(cv_imread)),
            ("OpenCV read_bytes + cv2.imdecode IMREAD_UNCHANGED", per_frame_ms(cv_imdecode)),
        ]
    cv2.setNumThreads(1)
    print(f"640x480 grey PNG of a simulated frame, {len(data) / 1024:.0f} KiB, one thread\n")
    print("| decoder | ms per frame | frames/s | vs Pillow |")
    print("|---|---:|---:|---:|")
    base = rows[1][1]
    for name, ms in rows:
        print(f"| {name} | {ms:.2f} | {1e3 / ms:.0f} | {base / ms:.2f}x |")


if __name__ == "__main__":
    cv2.setNumThreads(1)
    main()
