"""Calibration (paper III.B): from images of a known floor pattern to a ground lookup table
(a physical camera model fitted, with a predicted error per node), with an error report and an
overlay picture (the paper's Fig. 1c); and checking a table on another image.

Start at :func:`calibrate` (its example calibrates a simulated photo); docs/calibration.md.
"""

from .build import calibrate
from .camera_model import CameraModel
from .check import TableCheck, check_table
from .detect import Detection, detect
from .intrinsics import Intrinsics
from .lens_family import FAMILIES, LensFamily
from .options import CalibrationOptions, Coverage
from .overlay import draw_calibration_overlay
from .pattern import Pattern, PatternKind
from .region import FieldOfView, field_of_view
from .report import CalibrationReport, RangeRing

__all__ = [
    "FAMILIES",
    "CalibrationOptions",
    "CalibrationReport",
    "CameraModel",
    "Coverage",
    "Detection",
    "FieldOfView",
    "Intrinsics",
    "LensFamily",
    "Pattern",
    "PatternKind",
    "RangeRing",
    "TableCheck",
    "calibrate",
    "check_table",
    "detect",
    "draw_calibration_overlay",
    "field_of_view",
]
