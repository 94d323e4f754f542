from . import drive as drive, formats as formats, mapping as mapping, ranging as ranging, sim as sim
from typing import Final

__all__ = ["__version__", "_panic_for_tests", "drive", "formats", "mapping", "ranging", "sim"]

__version__: Final[str]
"""
The package version (the crates').
"""

def _panic_for_tests() -> None:
    """
    Panics inside [`errors::guard`], for the test that a panic reaches Python as
    `floorscan.errors.InternalError` (never `PanicException`).
    """
