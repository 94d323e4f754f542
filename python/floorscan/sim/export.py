"""Writing a simulated run as a dataset folder in the public format of
docs/dataset-format.md: ``images.txt`` + ``images/``, ``odometry.txt`` and ``groundtruth.txt``
(TUM), ``rig.toml``, ``calibration/pattern.png`` + ``pattern.toml``, and the simulator's truth
in ``truth/``.

The folder is built beside its destination and renamed into place when complete, so a dataset
folder is never seen half-written.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import List, Optional

import numpy as np

from .._atomic import PathLike
from ..errors import DatasetError, OptionError
from .calibration import PATTERN_KINDS, render_calibration
from .run import Run

TUM_HEADER = "# timestamp tx ty tz qx qy qz qw"


def tum_lines(timestamps: np.ndarray, poses: np.ndarray) -> List[str]:
    """TUM trajectory lines ``timestamp tx ty tz qx qy qz qw`` of planar poses (N, 3)."""
    half = 0.5 * poses[:, 2]
    return [
        f"{t:.6f} {x:.9f} {y:.9f} 0.0 0.0 0.0 {qz:.12f} {qw:.12f}"
        for t, x, y, qz, qw in zip(timestamps, poses[:, 0], poses[:, 1], np.sin(half), np.cos(half))
    ]


def rig_toml(rig: dict) -> str:
    return (
        "# Camera placement on the robot (floorscan dataset format, docs/dataset-format.md).\n"
        "[camera]\n"
        f"x = {rig['x']!r}   # m: camera ground frame origin in the robot base frame, forward\n"
        f"y = {rig['y']!r}   # m: left\n"
        f"yaw = {rig['yaw']!r}   # rad: heading of the camera ground frame on the robot (pan)\n"
        f"height = {rig['height']!r}   # m: optical centre above the floor\n"
    )


def _save_png(path: Path, image: np.ndarray, compress_level: int) -> None:
    from PIL import Image

    Image.fromarray(np.ascontiguousarray(image)).save(
        path, format="PNG", compress_level=compress_level
    )


def write_dataset(
    run: Run,
    folder: PathLike,
    *,
    calibration: Optional[str] = "checkerboard",
    truth: bool = True,
    labels: bool = True,
    map_resolution_m: float = 0.05,
    overwrite: bool = False,
    compress_level: int = 1,
) -> Path:
    """Writes ``run`` to ``folder`` (which must not exist, or be empty, unless ``overwrite``).

    ``calibration``: ``"checkerboard"``, ``"lines"`` or None: the calibration scene rendered
    with the run's camera into ``calibration/``. ``truth``: write ``truth/`` (columns CSV,
    occupancy map at ``map_resolution_m`` [m], exact camera, world file; ``labels`` adds the
    per-pixel label images). ``compress_level``: PNG compression, 0-9. Returns the folder.
    """
    if calibration is not None and calibration not in PATTERN_KINDS:
        raise OptionError(
            f"invalid option `calibration`: expected one of {PATTERN_KINDS} or None, "
            f"got {calibration!r}"
        )
    folder = Path(folder)
    if folder.exists() and not overwrite and (not folder.is_dir() or any(folder.iterdir())):
        raise DatasetError(f"{folder} exists and is not empty (pass overwrite=True to replace it)")
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{folder.name}.", suffix=".tmp", dir=folder.parent))
    try:
        _write(run, tmp, calibration, truth, labels, map_resolution_m, compress_level)
        if folder.exists():
            trash = Path(
                tempfile.mkdtemp(prefix=f".{folder.name}.", suffix=".old", dir=folder.parent)
            )
            os.replace(folder, trash / "old")
            os.replace(tmp, folder)
            shutil.rmtree(trash, ignore_errors=True)
        else:
            os.replace(tmp, folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return folder


def _write(
    run: Run, out: Path, calibration, truth, labels, map_resolution_m, compress_level
) -> None:
    n = len(run)
    names = [f"images/{k:06d}.png" for k in range(n)]
    (out / "images").mkdir()
    for k in range(n):
        _save_png(out / names[k], run.images[k], compress_level)
    header = [
        "# floorscan dataset (docs/dataset-format.md): <timestamp [s]> <image path>",
        f"# simulated: world {run.world.name}, seed {run.seed}, "
        f"{run.camera.width}x{run.camera.height}",
    ]
    (out / "images.txt").write_text(
        "\n".join(header + [f"{t:.6f} {p}" for t, p in zip(run.timestamps, names)]) + "\n",
        encoding="utf-8",
    )
    (out / "odometry.txt").write_text(
        "\n".join(
            ["# wheel odometry of the robot base (TUM format)", TUM_HEADER]
            + tum_lines(run.timestamps, run.odometry)
        )
        + "\n",
        encoding="utf-8",
    )
    (out / "groundtruth.txt").write_text(
        "\n".join(
            ["# true pose of the robot base (TUM format)", TUM_HEADER]
            + tum_lines(run.timestamps, run.poses)
        )
        + "\n",
        encoding="utf-8",
    )
    (out / "rig.toml").write_text(rig_toml(run.camera.rig()), encoding="utf-8")
    if calibration is not None:
        (out / "calibration").mkdir()
        image, pattern = render_calibration(run.camera, kind=calibration, seed=run.seed)
        _save_png(out / "calibration" / "pattern.png", image, compress_level)
        (out / "calibration" / "pattern.toml").write_text(pattern.to_toml(), encoding="utf-8")
    if truth:
        _write_truth(run, out / "truth", labels, map_resolution_m, compress_level)


def _write_truth(
    run: Run, out: Path, labels: bool, map_resolution_m: float, compress_level: int
) -> None:
    out.mkdir()
    if run.truth is not None:
        (out / "columns.csv").write_text(run.truth.to_csv(run.timestamps), encoding="utf-8")
    lines = ["frame,timestamp,x,y,yaw,exposure"] + [
        f"{k},{t:.6f},{p[0]:.9f},{p[1]:.9f},{p[2]:.9f},{e:.6f}"
        for k, (t, p, e) in enumerate(zip(run.timestamps, run.poses, run.exposures))
    ]
    (out / "frames.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    if labels and run.labels is not None:
        (out / "labels").mkdir()
        for k in range(len(run)):
            _save_png(out / "labels" / f"{k:06d}.png", run.labels[k], compress_level)
    run.world.occupancy(resolution_m=map_resolution_m).write_map_server(out / "map.yaml")
    (out / "camera.json").write_text(run.camera.to_json() + "\n", encoding="utf-8")
    if run.world.source is not None:
        (out / "world.toml").write_text(run.world.source, encoding="utf-8")
