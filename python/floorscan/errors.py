"""Exceptions raised by floorscan. Every error is a :class:`FloorscanError`; most are also a
:class:`ValueError` (bad values) or :class:`TypeError` (bad types), so generic handlers work.

Each core (Rust) error variant maps to exactly one class here.
"""

from __future__ import annotations


class FloorscanError(Exception):
    """Base class of every error floorscan raises on purpose."""


class ImageError(FloorscanError, ValueError):
    """An image has the wrong dtype, shape or size, is empty, or cannot be read."""


class ImageTooLargeError(ImageError):
    """An image's header declares more pixels than ``[limits] max_image_pixels`` allows (refused
    before any pixel is decoded)."""


class ImageTypeError(ImageError, TypeError):
    """An image is not a numpy array of a supported dtype."""


class ArgumentTypeError(FloorscanError, TypeError):
    """An argument has the wrong type or shape (the message names it and what was expected)."""


class OptionError(FloorscanError, ValueError):
    """An option or configuration value is outside its valid range (the message names it)."""


class ConfigError(OptionError):
    """A configuration file has an unknown or ill-typed key (the message names it)."""


class TableError(FloorscanError, ValueError):
    """A ground lookup table is inconsistent."""


class FileFormatError(FloorscanError, ValueError):
    """A file is damaged, truncated, or not of the expected kind."""


class UnsupportedVersionError(FileFormatError):
    """A file was written with a schema version this build does not read."""


class GeometryError(FloorscanError, ValueError):
    """A pose, range or point is not finite or outside its domain."""


class LengthMismatchError(FloorscanError, ValueError):
    """Arrays whose lengths must agree do not."""


class OutOfBoundsError(FloorscanError, ValueError):
    """A position lies outside a map with fixed bounds."""


class CalibrationError(FloorscanError, ValueError):
    """A calibration pattern could not be found or fitted (the message says what to check)."""


class DatasetError(FloorscanError, ValueError):
    """A dataset folder, log or bag is missing parts or holds malformed lines."""


class WorldError(FileFormatError):
    """A simulator world file is invalid (the message names the line or the field)."""


class OutputError(FloorscanError, OSError):
    """An output path cannot be written (a folder, read-only, under a file, too long, ...)."""


class MiddlewareError(FloorscanError, RuntimeError):
    """The robot's middleware (a ROS 1 master, rospy, Zenoh) is missing or unreachable."""


class InternalError(FloorscanError, RuntimeError):
    """A bug in floorscan (a Rust panic caught at the FFI boundary); please report it."""


__all__ = [
    "FloorscanError",
    "ImageError",
    "ImageTypeError",
    "ArgumentTypeError",
    "OptionError",
    "ConfigError",
    "TableError",
    "FileFormatError",
    "UnsupportedVersionError",
    "GeometryError",
    "LengthMismatchError",
    "OutOfBoundsError",
    "CalibrationError",
    "DatasetError",
    "WorldError",
    "OutputError",
    "MiddlewareError",
    "InternalError",
]
