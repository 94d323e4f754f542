"""The public dataset folder format (see docs/formats.md): ``images.txt`` lists
``<timestamp> images/<index>.png`` lines (``#`` comments allowed), ``odometry.txt`` and
``groundtruth.txt`` are TUM trajectories, ``rig.toml`` places the camera on the robot."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import List, Tuple

from .._atomic import PathLike
from ..errors import DatasetError


@dataclass(frozen=True)
class ImageEntry:
    timestamp: float
    path: Path


def read_images_txt(folder: PathLike) -> List[ImageEntry]:
    """The frames of a dataset folder, in file order; malformed lines name their line number."""
    folder = Path(folder)
    index = folder / "images.txt"
    try:
        lines = index.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as e:
        raise DatasetError(f"{index}: not UTF-8 text ({e})") from None
    except OSError as e:
        raise DatasetError(
            f"{folder} is not a dataset folder: cannot read images.txt ({e})"
        ) from None
    entries: List[ImageEntry] = []
    for lineno, line in enumerate(lines, start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split()
        if len(parts) != 2:
            raise DatasetError(
                f"{index}:{lineno}: expected '<timestamp> <image path>', got {line!r}"
            )
        try:
            t = float(parts[0])
        except ValueError:
            raise DatasetError(
                f"{index}:{lineno}: timestamp {parts[0]!r} is not a number"
            ) from None
        if not math.isfinite(t):
            raise DatasetError(f"{index}:{lineno}: timestamp {parts[0]!r} is not finite")
        if entries and t <= entries[-1].timestamp:
            raise DatasetError(
                f"{index}:{lineno}: timestamp {t} is not after the previous one "
                f"({entries[-1].timestamp}): images.txt must be in increasing time order"
            )
        if "\x00" in parts[1]:
            raise DatasetError(f"{index}:{lineno}: the image path holds a NUL byte")
        entries.append(ImageEntry(t, folder / parts[1]))
    return entries


def is_dataset_folder(path: PathLike) -> bool:
    return (Path(path) / "images.txt").is_file()


def image_inputs(paths: List[PathLike]) -> List[Tuple[float, Path]]:
    """(timestamp, image path) for command-line inputs: image files get their index as
    timestamp; dataset folders give the timestamps of their images.txt."""
    out: List[Tuple[float, Path]] = []
    index = 0
    for p in paths:
        p = Path(p)
        if p.is_dir():
            if not is_dataset_folder(p):
                raise DatasetError(f"{p} is a folder without images.txt (not a floorscan dataset)")
            out.extend((e.timestamp, e.path) for e in read_images_txt(p))
        else:
            out.append((float(index), p))
            index += 1
    return out
