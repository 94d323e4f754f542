"""Calibration (paper III.B): from one image of a known floor pattern to a ground lookup table,
with an error report and an overlay picture (the paper's Fig. 1c).

>>> from floorscan.calibration import calibrate            # doctest: +SKIP
>>> table, report = calibrate(image, "pattern.toml")       # doctest: +SKIP
>>> print(report.summary())                                # doctest: +SKIP
"""

from .build import calibrate
from .detect import Detection, detect
from .model import RadialPlaneModel
from .options import CalibrationOptions
from .overlay import draw_calibration_overlay
from .pattern import Pattern, PatternKind
from .region import FieldOfView, field_of_view
from .report import CalibrationReport

__all__ = [
    "CalibrationOptions",
    "CalibrationReport",
    "Detection",
    "FieldOfView",
    "Pattern",
    "PatternKind",
    "RadialPlaneModel",
    "calibrate",
    "detect",
    "draw_calibration_overlay",
    "field_of_view",
]
