"""What an evaluation scores: frames, poses and ground truth, from the simulator or from any
dataset folder with truth in the documented form (docs/dataset-format.md, ``truth/``)."""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Optional, Sequence, Tuple

import numpy as np

from .._atomic import PathLike
from ..errors import FileFormatError
from ..formats.dataset import read_images_txt
from ..formats.image_io import read_grey
from ..formats.rig import read_rig
from ..formats.trajectory import read_tum
from ..mapping.grid import OccupancyGrid
from ..ranging.ground_table import GroundTable
from ..ranging.scan import ColumnStatus

PoseTuple = Tuple[float, float, float]


@dataclass
class TruthRaster:
    """A true occupancy raster: ``cells`` (H, W) int16 (100 occupied, 0 free, -1 unknown; row 0
    = lowest y), ``origin`` = lower-left corner [m], ``resolution_m`` [m/cell]."""

    cells: np.ndarray
    origin: Tuple[float, float]
    resolution_m: float


@dataclass
class EvalCase:
    """One run to score.

    - ``images``: (N, H, W) uint8 frames (or a sequence of (H, W) arrays).
    - ``timestamps``: (N,) [s].
    - ``true_poses``: (N, 3) world_from_robot (x, y, yaw) or None.
    - ``odometry``: (N, 3) odometry poses (the product's input) or None.
    - ``robot_from_camera``: the camera ground frame on the robot (x, y, yaw).
    - ``true_status`` (N, W) status codes, ``true_points`` (N, W, 2) [m] camera ground frame,
      ``true_rows`` (N, W) [px]: per-column truth, or None.
    - ``raster``: the true occupancy, or None.
    - ``table``: the ground table the ranger uses; ``calibration``: its error figures.
    """

    name: str
    images: Any
    timestamps: np.ndarray
    table: GroundTable
    robot_from_camera: PoseTuple = (0.0, 0.0, 0.0)
    true_poses: Optional[np.ndarray] = None
    odometry: Optional[np.ndarray] = None
    true_status: Optional[np.ndarray] = None
    true_points: Optional[np.ndarray] = None
    true_rows: Optional[np.ndarray] = None
    raster: Optional[TruthRaster] = None
    calibration: Dict[str, Any] = field(default_factory=dict)
    info: Dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.timestamps)


def case_from_run(name: str, run, table: GroundTable, *, cell_size_m: float) -> EvalCase:
    """An :class:`EvalCase` from a simulated :class:`floorscan.sim.Run` with truth."""
    raster = run.world.occupancy(resolution_m=cell_size_m)
    return EvalCase(
        name=name,
        images=run.images,
        timestamps=np.asarray(run.timestamps, dtype=np.float64),
        table=table,
        robot_from_camera=tuple(run.camera.robot_from_camera),
        true_poses=np.asarray(run.poses, dtype=np.float64),
        odometry=np.asarray(run.odometry, dtype=np.float64),
        true_status=np.asarray(run.truth.status),
        true_points=np.asarray(run.truth.points, dtype=np.float64),
        true_rows=np.asarray(run.truth.rows, dtype=np.float64),
        raster=TruthRaster(raster.cells, tuple(raster.origin), raster.resolution_m),
    )


def read_truth_columns(path: PathLike, timestamps: Sequence[float], width: int):
    """``truth/columns.csv`` as arrays (status (N, W), points (N, W, 2), rows (N, W)) aligned
    with the dataset's frames (matched by the ``frame`` index)."""
    path = Path(path)
    n = len(timestamps)
    status = np.full((n, width), ColumnStatus.INVALID, np.int64)
    points = np.full((n, width, 2), np.nan)
    rows = np.full((n, width), np.nan)
    codes = {s.name.lower(): int(s) for s in ColumnStatus}
    try:
        with path.open(newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            need = {"frame", "column", "status", "row", "x", "y"}
            missing = need - set(reader.fieldnames or [])
            if missing:
                raise FileFormatError(f"{path}: missing columns {sorted(missing)}")
            for lineno, rec in enumerate(reader, start=2):
                try:
                    k, u = int(rec["frame"]), int(rec["column"])
                    code = codes[rec["status"]]
                    row, x, y = float(rec["row"]), float(rec["x"]), float(rec["y"])
                except (KeyError, ValueError, TypeError):  # TypeError: a short line's None
                    raise FileFormatError(
                        f"{path}:{lineno}: bad frame/column/status/row/x/y"
                    ) from None
                if 0 <= k < n and 0 <= u < width:
                    status[k, u] = code
                    rows[k, u] = row
                    points[k, u] = (x, y)
    except UnicodeDecodeError as e:
        raise FileFormatError(f"{path}: not UTF-8 text ({e.reason})") from None
    except csv.Error as e:
        raise FileFormatError(f"{path}: not a CSV file ({e})") from None
    except OSError as e:
        raise FileFormatError(f"cannot read truth columns {path}: {e}") from None
    return status, points, rows


def read_truth_map(path: PathLike) -> TruthRaster:
    """A map_server map (``map.yaml``) as a :class:`TruthRaster`."""
    grid = OccupancyGrid.load(path)
    classes = grid.occupancy_classes()
    cells = np.full(classes.shape, -1, np.int16)
    cells[classes == 0] = 0
    cells[classes == 2] = 100
    ext = grid.extent
    return TruthRaster(cells, tuple(ext.origin_m), ext.cell_size_m)


def _poses_at(path: Path, timestamps: np.ndarray) -> Optional[np.ndarray]:
    if not path.is_file():
        return None
    traj = read_tum(path)
    out = np.full((len(timestamps), 3), np.nan)
    for i, t in enumerate(timestamps):
        p = traj.pose_at(float(t))
        if p is not None:
            out[i] = p.as_tuple()
    return out


def case_from_dataset(
    dataset: PathLike, truth_dir: PathLike, table: GroundTable, *, name: Optional[str] = None
) -> EvalCase:
    """An :class:`EvalCase` from a dataset folder and a truth folder holding ``columns.csv``
    and/or ``map.yaml`` (map_server); true poses from the dataset's ``groundtruth.txt``."""
    dataset, truth_dir = Path(dataset), Path(truth_dir)
    entries = read_images_txt(dataset)
    timestamps = np.array([e.timestamp for e in entries], dtype=np.float64)
    images = [read_grey(e.path) for e in entries]
    columns = truth_dir / "columns.csv"
    map_yaml = truth_dir / "map.yaml"
    if not columns.is_file() and not map_yaml.is_file():
        raise FileFormatError(
            f"{truth_dir} holds neither columns.csv nor map.yaml (docs/dataset-format.md, truth/)"
        )
    status = points = rows = None
    if columns.is_file():
        status, points, rows = read_truth_columns(columns, timestamps, table.image_width)
    rig = read_rig(dataset / "rig.toml") if (dataset / "rig.toml").is_file() else None
    mount = (0.0, 0.0, 0.0)
    if rig is not None:
        mount = tuple(float(v) for v in rig.robot_from_camera)
    return EvalCase(
        name=name or dataset.name,
        images=images,
        timestamps=timestamps,
        table=table,
        robot_from_camera=mount,
        true_poses=_poses_at(dataset / "groundtruth.txt", timestamps),
        odometry=_poses_at(dataset / "odometry.txt", timestamps),
        true_status=status,
        true_points=points,
        true_rows=rows,
        raster=read_truth_map(map_yaml) if map_yaml.is_file() else None,
    )
