"""floorscan: one cheap camera as a laser-like range sensor, fused into occupancy maps.

An implementation of Howard & Kitchen, *Fast Visual Mapping for Mobile Robot Navigation*.
Conventions: SI units, REP 103 frames (x forward, y left, angles counter-clockwise in
radians), REP 117 ranges (+inf no return), image rows counted from the top.
"""

# isort: off
from . import _startup  # noqa: F401  (first: a Ctrl-C while importing exits quietly)

# isort: on
from . import _native
from .errors import (
    CalibrationError,
    ConfigError,
    DatasetError,
    FileFormatError,
    FloorscanError,
    GeometryError,
    ImageError,
    ImageTooLargeError,
    ImageTypeError,
    InternalError,
    LengthMismatchError,
    OptionError,
    OutOfBoundsError,
    OutputError,
    TableError,
    UnsupportedVersionError,
    WorldError,
)
from .mapping.evidence import EvidenceMap, merge_evidence
from .mapping.grid import InsertStats, OccupancyGrid
from .mapping.grid_options import Evidence
from .mapping.grid_views import GridExtent
from .mapping.local_map import LocalMap
from .mapping.log_odds import Occupancy
from .ranging.appearance import AppearanceRanger
from .ranging.ground_table import GroundTable
from .ranging.lens import CameraMount, Lens
from .ranging.ranger import Refinement, VisualRanger
from .ranging.scan import SCAN_CSV_HEADER, ColumnStatus, Scan, read_scans_csv, write_scans_csv

__version__ = _native.__version__

__all__ = [
    "CalibrationError",
    "CameraMount",
    "ColumnStatus",
    "ConfigError",
    "DatasetError",
    "Evidence",
    "EvidenceMap",
    "FileFormatError",
    "FloorscanError",
    "GeometryError",
    "GridExtent",
    "GroundTable",
    "ImageError",
    "ImageTooLargeError",
    "ImageTypeError",
    "InternalError",
    "InsertStats",
    "Lens",
    "LengthMismatchError",
    "LocalMap",
    "Occupancy",
    "OccupancyGrid",
    "OptionError",
    "OutOfBoundsError",
    "OutputError",
    "Refinement",
    "SCAN_CSV_HEADER",
    "Scan",
    "TableError",
    "UnsupportedVersionError",
    "VisualRanger",
    "AppearanceRanger",
    "merge_evidence",
    "read_scans_csv",
    "write_scans_csv",
    "WorldError",
    "calibrate",
    "CalibrationReport",
    "Pattern",
]

# Calibration needs OpenCV, which takes a second to import: loaded on first use.
_CALIBRATION_NAMES = {"calibrate", "CalibrationReport", "Pattern"}


def __getattr__(name: str):
    if name in _CALIBRATION_NAMES:
        from . import calibration

        return getattr(calibration, name)
    raise AttributeError(f"module 'floorscan' has no attribute {name!r}")
