"""One check of a configuration, shared by ``floorscan config --check`` and ``floorscan run``:
it builds (and drops) every component ``run`` builds from the configuration alone, with the
same constructors, so the two accept and refuse exactly the same files.

What depends on the input is checked by ``run`` only: ``ranger.columns`` against the
calibration's image width and ``ranger.bottom_margin`` against its height.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from .. import _native
from ..calibration.options import CalibrationOptions
from ..errors import OptionError
from ..formats.image_io import check_max_image_pixels
from ..mapping.grid import OccupancyGrid
from ..mapping.local_map import LocalMap
from ..ranging.ranger import build_ranger_options
from .config import Config
from .mapper import grid_kwargs
from .node_options import check_node
from .outputs import check_outputs

WIDEST_IMAGE_PX = 1 << 16
"""The largest image a ground table may declare (floorscan-core's MAX_IMAGE_SIDE_PX): the
input-independent bound on ``columns`` and ``bottom_margin``."""


def check_ranger(cfg: Config) -> None:
    r = cfg.ranger
    options = build_ranger_options(
        image_width=WIDEST_IMAGE_PX,
        image_height=WIDEST_IMAGE_PX,
        columns=r.columns,
        half_width=r.half_width,
        threshold=r.threshold,
        refine=r.refine,
        bottom_margin=r.bottom_margin,
        mask=None,
        max_range_m=r.max_range_m,
    )
    _native.validate_ranger_options(json.dumps(options))
    if not (math.isfinite(r.auto_threshold_k) and r.auto_threshold_k > 0):
        raise OptionError(
            f"invalid option `ranger.auto_threshold_k`: must be finite and > 0, got {r.auto_threshold_k}"
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
    LocalMap(size_m=cfg.map.local_size_m, **kw)
    check_outputs(cfg.outputs)
    check_max_image_pixels(cfg.limits.max_image_pixels)
    check_node(cfg.node)
    return cfg
