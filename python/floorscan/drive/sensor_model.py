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

Where the defaults come from: :func:`floorscan.drive.sensor_fit.fit_sensor_model` estimates
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

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any, Dict

import numpy as np

from ..errors import OptionError


@dataclass(frozen=True)
class VisualSensorModel:
    """Parameters (logits are natural-log odds of the cell being occupied).

    - ``free_a``, ``free_b`` [1, 1/m]: logit P(occupied | seen free at range r) = a + b r.
      Defaults -3.2, 0.55 (see the module docstring).
    - ``hit_a``, ``hit_b`` [1, 1/m]: logit P(occupied | boundary cell at range r) = a + b r.
      Defaults 2.0, -0.45 (see the module docstring).
    - ``too_close_logit``: logit P(occupied) at the near edge of a ``too_close`` column.
      Default 1.0 (fitted share of too_close near edges that touch an obstacle).
    - ``margin_sigmas``: floor left unobserved before a boundary, in sigmas, in [0, 10].
      Default 2 (95 % of the boundary's position errors lie within 2 sigma).
    - ``default_error_m`` [m]: e where the table predicts none, > 0. Default 0.01 (the
      calibration's typical error bar inside the pattern, docs/calibration.md).
    - ``fusion_weight``: evidence multiplier per frame, in (0, 1]. Default 0.7; the
      correlation of successive frames is corrected once more on the map's output
      (``AvoidanceMapOptions.probability_scale``).
    - ``no_boundary_clearing``: the share, in [0, 1], of its free evidence that the floor
      beside a ``no_boundary`` column adds to a cell the map believes occupied (log odds
      above ``confirmed_nats``); floor between two boundary columns clears in full, and
      unknown or free cells take any column's free evidence in full. Default 0: a column that
      finds no edge over an obstacle mapped from farther away (a face the colour of the
      floor) does not clear it, as a ROS costmap does not clear through a laser's no-return
      beams; the obstacle fades with ``AvoidanceMapOptions.half_life_s`` or is cleared by a
      column that sees the floor end beyond it. 1 is the model as it was: on the four
      held-out worlds (64 runs) 1 gave 3 collisions at 0.3 m/s, 0 gives none, at 1.20x the
      laser robot's time against 1.14x (EVALUATION.md, "A column without a boundary does not
      clear a mapped obstacle").
    - ``confirmed_nats``: log odds (>= 0) above which a cell counts as believed occupied for
      ``no_boundary_clearing``. Default 0 (more likely occupied than not). 1.5 (two
      readings) was measured: it gave back the time (1.14x) but not the safety (1 collision
      at 0.3 m/s, 7 at 0.5 m/s in the same 64 runs).
    - ``confirm_range_m``: least range [m] (>= 0) of a boundary whose hit makes its cells
      believed obstacles for ``no_boundary_clearing``; a cell only ever hit from nearer is
      cleared in full by any column that sees floor over it. Default 0.3: the obstacles the
      rule is for were mapped from farther away (a desk's face the colour of the floor, a
      light leg), while flecks of a light carpet read as edges lie 0.1-0.3 m from the camera,
      where the floor's grain is magnified; without it such a fleck stayed in the map until
      it faded and held the robot in place (a cafe on a light carpet: 2.6x the laser robot's
      time, 85 % of waypoints). 0.5, the first value, let a desk and a leg confirmed only
      from 0.3-0.5 m be cleared (2 contacts at 0.3 m/s in 32 runs); EVALUATION.md, "Flecks of
      a light carpet". 0: every hit confirms (the rule as it was).
    - ``confirmed_clearing``: the share, in (0, 1], of its free evidence that floor between
      two boundary columns adds, in the planner's layer of the avoidance map
      (``AvoidanceMap.plan_log_odds``), to a cell believed occupied (as for
      ``no_boundary_clearing``) and confirmed by a hit from ``confirm_range_m`` or farther;
      the map's own log odds, whose calibrated probabilities say how often a cell is
      occupied, clear in full (held in them too, a disproved obstacle's moderate evidence
      put three middle deciles of the reliability diagram 9-14 points above what was
      observed).
      Default 0.25, chosen before any run with it: OctoMap's ratio of miss to hit evidence
      (0.4 / 0.85 nats = 0.47) carried over to this model's evidence at 1 m (free -1.86
      nats a frame, hit +1.09): 0.47 x 1.09 / 1.86 = 0.28, rounded down. A saturated
      obstacle's cell then clears over about eight frames of floor seen beyond it, not two. A thin
      leg the camera loses close up, finding the floor's end beyond it, cleared it in three
      frames, a second before the robot touched it (EVALUATION.md, "A thin leg clears over
      several frames"). Unconfirmed cells (a fleck near the robot) clear in full. 1: the
      planner's layer equals the map's (the model as it was).
    - ``persist_range_m``: range [m] (>= 0, camera frame) within which a hit (a boundary
      point, a ``too_close`` near edge) enters the planner's layers only when it persists:
      the previous insertion hit its cell or one of the eight around it from as near, or the
      planner already believes one of them occupied (``AvoidanceMap.plan_near_hits``); the
      map's own log odds take every hit. Default 0: every hit enters at once. On a pale
      grainy carpet the edge filter reads flecks at the image's bottom rows as boundaries
      0.15-0.45 m away, each a lethal cell beside the robot that sends the dynamic window
      into an escape (64 % of a library's frames); such a fleck is seen again at the same
      cell in the next frame in 9-50 % of cases, a real obstacle that near in 96-100 %.
      0.5 m there cut the time against the laser robot from 1.47x to 1.30x over ten
      held-out worlds, but contacts rose from 2 to 5 at 0.3 m/s and from 5 to 11 at 0.5 m/s
      (136 runs each; EVALUATION.md, "Near hits that do not persist"): an opt-in for
      carpets like those, not a default.
    """

    free_a: float = -3.2
    free_b: float = 0.55
    hit_a: float = 2.0
    hit_b: float = -0.45
    too_close_logit: float = 1.0
    margin_sigmas: float = 2.0
    default_error_m: float = 0.01
    fusion_weight: float = 0.7
    no_boundary_clearing: float = 0.0
    confirmed_nats: float = 0.0
    confirm_range_m: float = 0.3
    confirmed_clearing: float = 0.25
    persist_range_m: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if not isinstance(v, (int, float)) or not math.isfinite(float(v)):
                raise OptionError(f"invalid option `{f.name}`: must be a finite number, got {v!r}")
        if not 0.0 <= self.margin_sigmas <= 10.0:
            raise OptionError(
                f"invalid option `margin_sigmas`: must be in [0, 10], got {self.margin_sigmas}"
            )
        if self.default_error_m <= 0:
            raise OptionError(
                f"invalid option `default_error_m`: must be > 0, got {self.default_error_m}"
            )
        if not 0.0 <= self.no_boundary_clearing <= 1.0:
            raise OptionError(
                "invalid option `no_boundary_clearing`: must be in [0, 1], got "
                f"{self.no_boundary_clearing}"
            )
        if not self.confirmed_nats >= 0.0:
            raise OptionError(
                f"invalid option `confirmed_nats`: must be >= 0, got {self.confirmed_nats}"
            )
        if not self.confirm_range_m >= 0.0:
            raise OptionError(
                f"invalid option `confirm_range_m`: must be >= 0, got {self.confirm_range_m}"
            )
        if not self.persist_range_m >= 0.0:
            raise OptionError(
                f"invalid option `persist_range_m`: must be >= 0, got {self.persist_range_m}"
            )
        if not 0.0 < self.confirmed_clearing <= 1.0:
            raise OptionError(
                "invalid option `confirmed_clearing`: must be in (0, 1], got "
                f"{self.confirmed_clearing}"
            )
        if not 0.0 < self.fusion_weight <= 1.0:
            raise OptionError(
                f"invalid option `fusion_weight`: must be in (0, 1], got {self.fusion_weight}"
            )

    def with_(self, **changes: Any) -> VisualSensorModel:
        return replace(self, **changes)

    def as_dict(self) -> Dict[str, float]:
        return {k: float(v) for k, v in asdict(self).items()}

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
