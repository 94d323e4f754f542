"""floorscan: one cheap camera as a laser-like range sensor, fused into occupancy maps.

An implementation of Howard & Kitchen, *Fast Visual Mapping for Mobile Robot Navigation*.
Conventions: SI units, REP 103 frames (x forward, y left, angles counter-clockwise in
radians), REP 117 ranges (+inf no return), image rows counted from the top.
"""

# isort: off
from . import _startup  # noqa: F401  (first: a Ctrl-C while importing exits quietly)

# isort: on
from . import _native
from .appearance import AppearanceRanger
from .errors import (
    CalibrationError,
    ConfigError,
    DatasetError,
    FileFormatError,
    FloorscanError,
    GeometryError,
    ImageError,
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
from .evidence import EvidenceMap, merge_evidence
from .grid import InsertStats, OccupancyGrid
from .grid_options import Evidence
from .grid_views import GridExtent
from .ground_table import GroundTable
from .lens import CameraMount, Lens
from .local_map import LocalMap
from .ranger import VisualRanger
from .scan import SCAN_CSV_HEADER, Scan, read_scans_csv, write_scans_csv

__version__ = _native.__version__

__all__ = [
    "CalibrationError",
    "CameraMount",
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
    "ImageTypeError",
    "InternalError",
    "InsertStats",
    "Lens",
    "LengthMismatchError",
    "LocalMap",
    "OccupancyGrid",
    "OptionError",
    "OutOfBoundsError",
    "OutputError",
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
