"""The public dataset folder format (see docs/formats.md): ``images.txt`` lists
``<timestamp> images/<index>.png`` lines (``#`` comments allowed), ``odometry.txt`` and
``groundtruth.txt`` are TUM trajectories, ``rig.toml`` places the camera on the robot."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Tuple

import numpy as np

from ._atomic import PathLike
from .errors import DatasetError


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


def read_trajectory(path: PathLike) -> Tuple[np.ndarray, np.ndarray]:
    """A TUM trajectory file (``timestamp tx ty tz qx qy qz qw``, ``#`` comments) as planar
    poses: timestamps (N,) [s] and poses (N, 3) = (x [m], y [m], yaw [rad]); yaw from the
    quaternion's rotation about z (roll and pitch are ignored)."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError as e:
        raise DatasetError(f"cannot read trajectory {path}: {e}") from None
    rows = []
    for lineno, line in enumerate(lines, start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split()
        if len(parts) != 8:
            raise DatasetError(
                f"{path}:{lineno}: expected 'timestamp tx ty tz qx qy qz qw', got {line!r}"
            )
        try:
            rows.append([float(p) for p in parts])
        except ValueError:
            raise DatasetError(f"{path}:{lineno}: not numbers: {line!r}") from None
    a = np.array(rows, dtype=np.float64).reshape(-1, 8)
    qx, qy, qz, qw = a[:, 4], a[:, 5], a[:, 6], a[:, 7]
    yaw = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
    return a[:, 0], np.stack([a[:, 1], a[:, 2], yaw], axis=1)


def read_rig(folder: PathLike) -> Dict[str, float]:
    """The ``[camera]`` table of a dataset's ``rig.toml``: x, y [m], yaw [rad] of the camera
    ground frame on the robot base, and height [m] of the camera above the floor."""
    try:
        import tomllib  # type: ignore[import-not-found]
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib  # type: ignore[no-redef]

    path = Path(folder) / "rig.toml"
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as e:
        raise DatasetError(f"cannot read {path}: {e}") from None
    except tomllib.TOMLDecodeError as e:
        raise DatasetError(f"{path}: {e}") from None
    cam = data.get("camera")
    if not isinstance(cam, dict):
        raise DatasetError(f"{path}: missing table [camera]")
    out = {}
    for key in ("x", "y", "yaw", "height"):
        v = cam.get(key)
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise DatasetError(f"{path}: [camera].{key} must be a number, got {v!r}")
        out[key] = float(v)
    return out
