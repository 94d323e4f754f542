"""A calibrated inverse sensor model for visual scans: how much evidence one reading adds to a
cell, from what is known about the reading.

For a column reading with status ``boundary`` at range r [m] (camera ground frame), footprint f
(the floor length one pixel row covers there [m]) and the table's predicted floor-position
error e (``GroundTable.lookup_error`` [m]), the boundary's position is uncertain by
sigma = sqrt(e^2 + (f / 2)^2 + (cell / 2)^2). The model then says:

- floor from the near edge of view to ``margin_sigmas`` * sigma before the boundary is free,
  with P(occupied | seen free at range r) = logistic(free_a + free_b r);
- the cells within max(sigma, cell / 2) of the boundary (and of the face between two adjacent
  boundary points) are occupied with P = logistic(hit_a + hit_b r);
- ``no_boundary`` columns are free up to their farthest point, as above, except that they
  clear a cell the map already believes occupied only by ``no_boundary_clearing`` of that
  (default 0: a column that finds no edge is a laser's no-return beam, which a ROS costmap
  does not clear with);
- ``too_close`` columns mark the near edge of view occupied with P = logistic(too_close_logit);
- ``invalid`` columns say nothing.

Each probability becomes evidence (log odds against an even prior) times ``fusion_weight``.
Successive frames of a moving camera are correlated (the same carpet, the same errors), so
summed evidence overstates certainty; the avoidance map corrects that on its output with a
monotone calibration (``AvoidanceMapOptions.probability_knots``, fitted by isotonic
regression; or a Platt curve, ``probability_scale`` / ``probability_offset``).

Where the defaults come from: :func:`floorscan.evaluation.sensor_fit.fit_sensor_model` estimates
the four logits from simulator truth (``bench/drive_sensor_model.py``: corridor and room,
30 s each, seed 1, exact table), giving free -2.97 - 0.07 r and hit 2.0 - 0.99 r. Driven in
closed loop, those fitted values make the robot hesitate (hits beyond 2 m add free evidence
to the obstacle's cell, and the room's tour is not finished in 120 s), so the defaults are
the hand-set values below, chosen before the fit and checked in the closed loop (room tour:
0 contacts, 4 of 4 waypoints, 42 s); their map is then made to mean what it says by the
avoidance map's output calibration, fitted on the same truth. EVALUATION.md has both models'
reliability diagrams. ``floorscan tune`` keeps tuning the ranger and OctoMap-style constant
evidence; this model is the avoidance map's.
"""

from __future__ import annotations

from typing import Any, Dict

import numpy as np

from ..options import OptionsObject


class VisualSensorModel(OptionsObject, kind="visual_sensor_model"):
    """The model's parameters: the core's ``VisualModel`` (defaults, the reasons for each and
    every rule live there, ``crates/floorscan-core/src/navigation/visual_sensor_model.rs``;
    ``floorscan.options.field_docs("visual_sensor_model")`` reads them): ``free_a``,
    ``free_b``, ``hit_a``, ``hit_b``, ``too_close_logit``, ``margin_sigmas``,
    ``default_error_m``, ``fusion_weight``, ``no_boundary_clearing``, ``confirmed_nats``,
    ``confirm_range_m``, ``confirmed_clearing``, ``persist_range_m``. Keyword arguments are
    any of them (a bad one is an OptionError naming it); read-only.

    >>> VisualSensorModel(hit_a=1.5).hit_a, VisualSensorModel().confirm_range_m
    (1.5, 0.3)
    """

    __slots__ = ()

    def with_(self, **changes: Any) -> VisualSensorModel:
        return self.replace(**changes)

    def as_dict(self) -> Dict[str, float]:
        return {k: float(v) for k, v in self.to_dict().items()}

    def sigma_m(self, error_m: np.ndarray, footprint_m: np.ndarray, cell_size_m: float):
        """Boundary position uncertainty [m] (see the module docstring)."""
        e = np.where(np.isfinite(error_m), error_m, self.default_error_m)
        f = np.where(np.isfinite(footprint_m), footprint_m, 0.0)
        return np.sqrt(e * e + 0.25 * f * f + 0.25 * cell_size_m**2)

    def free_logit(self, range_m: np.ndarray) -> np.ndarray:
        return self.free_a + self.free_b * np.asarray(range_m)

    def hit_logit(self, range_m: np.ndarray) -> np.ndarray:
        return self.hit_a + self.hit_b * np.asarray(range_m)


def logistic(z):
    return 1.0 / (1.0 + np.exp(-np.asarray(z, dtype=np.float64)))
