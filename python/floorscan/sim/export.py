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
from typing import TYPE_CHECKING, Optional

import numpy as np

from .._atomic import PathLike
from ..errors import DatasetError, OptionError
from ..formats.rig import Rig
from ..formats.trajectory import Trajectory, tum_text
from .calibration import PATTERN_KINDS, render_calibration

if TYPE_CHECKING:  # only for annotations: run.py imports this module
    from .run import Run


def _trajectory_text(comment: str, timestamps: np.ndarray, poses: np.ndarray) -> str:
    """A TUM trajectory file's text (floorscan.formats.trajectory's writer) with a comment line."""
    traj = Trajectory(timestamps, poses[:, 0], poses[:, 1], poses[:, 2])
    return f"# {comment}\n" + tum_text(traj)


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
        _trajectory_text("wheel odometry of the robot base", run.timestamps, run.odometry),
        encoding="utf-8",
    )
    (out / "groundtruth.txt").write_text(
        _trajectory_text("true pose of the robot base", run.timestamps, run.poses),
        encoding="utf-8",
    )
    (out / "rig.toml").write_text(Rig(**run.camera.rig()).to_toml(), encoding="utf-8")
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
