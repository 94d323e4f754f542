"""Calibration error: a calibrated ground table against the camera's exact image-to-ground
mapping, at many pixels whose true ground range is within a limit (3 m)."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any, Dict, Optional, Tuple

import numpy as np

from ..calibration import calibrate
from ..errors import DatasetError
from ..formats.image_io import read_grey
from ..ranging.ground_table import GroundTable
from ..sim import Camera, render_calibration

NOT_AVAILABLE = "n/a (calibration not available)"


def calibration_available() -> bool:
    try:
        from ..calibration import calibrate  # noqa: F401
    except ImportError:
        return False
    return True


def table_error(
    table: GroundTable, camera, *, within_m: float = 3.0, step_px: int = 4
) -> Dict[str, Any]:
    """Max and RMS distance [cm] between ``table`` and the exact mapping of ``camera``
    (:class:`floorscan.sim.Camera`) on a pixel lattice every ``step_px`` pixels, over the pixels
    whose exact ground range is within ``within_m`` [m] (3 m, the range sensor's default
    maximum range) and that the table covers; also the share of those pixels the table covers
    (``covered_share``) and the share of the covered ones within the table's own predicted
    error (``within_predicted``, for tables that carry one)."""
    w, h = table.image_width, table.image_height
    us, vs = np.meshgrid(
        np.arange(0.0, w, step_px, dtype=np.float64), np.arange(0.0, h, step_px, dtype=np.float64)
    )
    us, vs = us.ravel(), vs.ravel()
    tx, ty = camera.pixel_to_ground(us, vs)
    tx, ty = np.asarray(tx, dtype=np.float64), np.asarray(ty, dtype=np.float64)
    within = np.isfinite(tx) & (np.hypot(tx, ty) <= within_m)
    cx, cy = table.lookup(us[within], vs[within])
    covered = np.isfinite(cx)
    err = np.hypot(cx[covered] - tx[within][covered], cy[covered] - ty[within][covered])
    if err.size == 0:
        return {"status": "no overlap", "max_cm": float("nan"), "rms_cm": float("nan")}
    extra = {}
    if table.error_m is not None:
        bar = table.lookup_error(us[within][covered], vs[within][covered])
        ok = np.isfinite(bar)
        if ok.any():
            extra["within_predicted"] = float(np.mean(err[ok] <= bar[ok]))
    return {
        **extra,
        "status": "measured",
        "max_cm": float(err.max() * 100),
        "rms_cm": float(np.sqrt(np.mean(err**2)) * 100),
        "pixels": int(err.size),
        "covered_share": float(covered.mean()),
        "within_m": within_m,
    }


def calibrated_table(
    camera, *, calibration: Optional[Dict[str, Any]] = None
) -> Tuple[GroundTable, Dict[str, Any]]:
    """The ground table ranging uses: calibrated from the simulated checkerboard scene when
    :mod:`floorscan.calibration` is available (with its error against the exact mapping, to
    3 m), else the camera's exact table (error reported as not available). ``calibration``:
    keyword options of :func:`floorscan.calibrate` (default: its defaults)."""
    calibration = dict(calibration or {})
    spacing_px = calibration.get("spacing_px", 8)
    if not calibration_available():
        return camera.ground_table(spacing_px=spacing_px), {"status": NOT_AVAILABLE}
    image, pattern = render_calibration(camera, kind="checkerboard")
    with tempfile.TemporaryDirectory(prefix="floorscan-eval-") as tmp:
        path = Path(tmp) / "pattern.toml"
        path.write_text(pattern.to_toml(), encoding="utf-8")
        table, _report = calibrate(image, path, **calibration)
    return table, table_error(table, camera)


def table_for_dataset(
    dataset: Path,
    truth_dir: Path,
    *,
    calibration: Optional[Dict[str, Any]] = None,
    table_path=None,
) -> Tuple[GroundTable, Dict[str, Any]]:
    """The table to range a dataset with, and its calibration error when measurable: a given
    table file; else calibrated from the dataset's ``calibration/`` scene (when calibration is
    available); else the exact table of ``truth/camera.json``. The error is measured against
    ``truth/camera.json`` when it exists."""
    calibration = dict(calibration or {})
    spacing_px = calibration.get("spacing_px", 8)
    dataset, truth_dir = Path(dataset), Path(truth_dir)
    camera = (
        Camera.load(truth_dir / "camera.json") if (truth_dir / "camera.json").is_file() else None
    )
    if table_path is not None:
        table = GroundTable.load(table_path)
    elif calibration_available() and (dataset / "calibration" / "pattern.toml").is_file():
        table, _ = calibrate(
            read_grey(dataset / "calibration" / "pattern.png"),
            dataset / "calibration" / "pattern.toml",
            **calibration,
        )
    elif camera is not None:
        return camera.ground_table(spacing_px=spacing_px), {
            "status": NOT_AVAILABLE + "; ranged with the exact table of truth/camera.json"
        }
    else:
        raise DatasetError(
            f"no ground table for {dataset}: give --table, or a dataset with calibration/ "
            "(and floorscan.calibration), or truth/camera.json"
        )
    if camera is None:
        return table, {"status": "not measured (no truth/camera.json)"}
    return table, table_error(table, camera)
