"""
Driving: the planner's navigation function and the scan matcher's search.
"""

from _typeshed import Incomplete, SupportsLenAndGetItem
from typing import SupportsFloat, SupportsIndex

def correlative_search(field: Incomplete, origin_m: tuple[SupportsFloat | SupportsIndex, SupportsFloat | SupportsIndex], cell_m: SupportsFloat | SupportsIndex, points: Incomplete, prior: SupportsLenAndGetItem[SupportsFloat | SupportsIndex], xy_steps: SupportsIndex, yaw_steps: SupportsIndex, yaw_step_rad: SupportsFloat | SupportsIndex, prior_xy_m: SupportsFloat | SupportsIndex, prior_yaw_rad: SupportsFloat | SupportsIndex) -> tuple[tuple[float, float, float], float, float]:
    """
    The best pose (x, y, yaw), its mean field value and its score for `points` (N, 2) float64
    [m, robot frame] around `prior` (world_from_robot): translations of -xy_steps..=xy_steps
    cells of `field` (H, W) float32 (values in [0, 1], row 0 = lowest y, cell (0, 0)'s corner
    at `origin_m`, cells `cell_m` wide), yaws of -yaw_steps..=yaw_steps times `yaw_step_rad`;
    score = mean field value x exp(-(|t| / prior_xy_m)^2 - (dyaw / prior_yaw_rad)^2); then
    refined below a cell on the field read bilinearly (`floorscan_core::scan_matcher::refine`).
    """

def geodesic_distances(blocked: Incomplete, weight: Incomplete, seed_cells: Incomplete, seed_costs: Incomplete, step_m: SupportsFloat | SupportsIndex) -> Incomplete:
    """
    Geodesic cost-to-goal (H, W) float64 [m, weighted] over an 8-connected grid: `blocked`
    (H, W) bool cells are never entered, a step costs its length (`step_m` or sqrt 2 times it)
    times the mean `weight` (H, W) float64 of its two cells; `seed_cells` (K,) int64 row-major
    cell indices start at `seed_costs` (K,) float64. `inf` where nothing reaches.
    """

def __getattr__(name: str) -> Incomplete: ...
