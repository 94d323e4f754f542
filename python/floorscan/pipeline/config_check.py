"""One check of a configuration, shared by ``floorscan config --check`` and ``floorscan run``:
it builds (and drops) every component ``run`` builds from the configuration alone, with the
same constructors, so the two accept and refuse exactly the same files.

The Rust options tables (``[ranger]``, ``[appearance]``, ``[grid]``, ``[local_map]``,
``[sensors]``) are read and validated by their Rust types when the file is loaded
(:class:`~floorscan.pipeline.config.Config`); here the map builders are built with them too.
What depends on the input (``ranger.columns`` against the image's width, ``ranger.start``
against its height) needs a ground table: :func:`check_config_for_table` builds the range
sensor ``run`` would build with it.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..calibration.options import CalibrationOptions
from ..errors import OptionError
from ..formats.image_io import check_max_image_pixels
from ..mapping.grid import OccupancyGrid
from ..mapping.local_map import LocalMap
from .config import Config
from .mapper import grid_kwargs, local_map_kwargs, ranger_from_config
from .node_options import check_node
from .outputs import check_outputs


def check_ranger(cfg: Config) -> None:
    """The pipeline's own ``[ranger]`` keys (the Rust options were checked when loaded)."""
    k = cfg.ranger.auto_threshold_k
    if not (math.isfinite(k) and k > 0):
        raise OptionError(
            f"invalid option `ranger.auto_threshold_k`: must be finite and > 0, got {k}"
        )


def check_calibration(cfg: Config) -> None:
    options = cfg.calibration.kwargs()
    intrinsics = options.pop("intrinsics", None)  # a file, read when calibrating
    CalibrationOptions(**options)
    if intrinsics is not None and not Path(intrinsics).is_file():
        raise OptionError(f"invalid option `calibration.intrinsics`: no file {intrinsics}")


def check_config(cfg: Config) -> Config:
    """Raises the error ``floorscan run`` would raise for this configuration (OptionError,
    ConfigError), else returns it."""
    check_ranger(cfg)
    check_calibration(cfg)
    kw = grid_kwargs(cfg)
    OccupancyGrid(**kw)
    LocalMap(**local_map_kwargs(cfg))
    check_outputs(cfg.outputs)
    check_max_image_pixels(cfg.limits.max_image_pixels)
    check_node(cfg.node)
    return cfg


def check_config_for_table(cfg: Config, table) -> Config:
    """:func:`check_config`, then the range sensor ``run`` builds from ``cfg`` and ``table``
    (a :class:`~floorscan.GroundTable`): the options that depend on the image's size
    (``ranger.columns``, ``ranger.start``) are refused as ``run`` refuses them."""
    check_config(cfg)
    ranger_from_config(table, cfg)
    return cfg
