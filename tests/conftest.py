"""Shared test helpers."""

from __future__ import annotations

import os
from pathlib import Path

import floorscan
import numpy as np
import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent


def shared_data_dir() -> Path:
    """`../shared/data` beside the repository (FLOORSCAN_DATA overrides it)."""
    env = os.environ.get("FLOORSCAN_DATA")
    if env:
        return Path(env)
    for candidate in (REPO_ROOT.parent / "shared" / "data", Path("/work/shared/data")):
        if candidate.is_dir():
            return candidate
    return REPO_ROOT.parent / "shared" / "data"


def require_shared_data(*parts: str) -> Path:
    path = shared_data_dir().joinpath(*parts)
    if not path.exists():
        pytest.skip(
            f"real data not available: {path} is absent (set FLOORSCAN_DATA to ../shared/data)"
        )
    return path


def affine_table(
    width: int = 64, height: int = 48, spacing: int = 4, horizon: float = 0.0
) -> floorscan.GroundTable:
    """A table with ground below `horizon` rows: x grows up the image, y to the left."""

    def ground(u, v):
        x = 0.2 + (height - 1 - v) * 0.01
        y = (width / 2 - u) * 0.005
        return np.where(v >= horizon, x, np.nan), y

    return floorscan.GroundTable.from_function(
        ground, image_width=width, image_height=height, spacing_px=spacing
    )


@pytest.fixture
def table64() -> floorscan.GroundTable:
    return affine_table()
