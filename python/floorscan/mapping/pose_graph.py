"""A 2-D pose graph: keyframe poses joined by sequential edges (the local trajectory between
consecutive keyframes) and loop closures (a keyframe matched against keyframes it passes
again), optimised by GTSAM's Levenberg-Marquardt (Dellaert and Kaess; the solver
slam_toolbox's peers use), a Cauchy loss on the loop closures so that a wrong one weighs little
once the rest disagree with it.

GTSAM is an optional dependency (``pip install 'floorscan[slam]'``): :data:`AVAILABLE` says
whether it is installed; building a :class:`PoseGraph` without it raises
:class:`~floorscan.ConfigError` with the line that installs it. Chosen by a side-by-side on
the graph of the Freiburg 079 log (1525 keyframes, 2165 edges, 641 loop closures; the same
cost function): GTSAM 0.12 s, SciPy's sparse trust-region least squares 12.4 s to the same
cost (BENCHMARKS.md, "Pose graph solvers").

Options: the Rust ``PoseGraphOptions`` (``[slam.graph]``; defaults, docs and rules in
``crates/floorscan-core/src/mapping/pose_graph_options.rs``).
"""

from __future__ import annotations

import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .._native.mapping import pose_graph_field_half_side_m
from ..errors import ConfigError
from ..options import OptionsObject

try:
    import gtsam
except ImportError:  # the optional extra is not installed
    gtsam = None

AVAILABLE = gtsam is not None
"""Whether GTSAM is installed (loop closure over a pose graph needs it)."""

INSTALL_HINT = "pip install 'floorscan[slam]' (GTSAM)"

PoseTuple = Tuple[float, float, float]
Edge = Tuple[int, int, PoseTuple, PoseTuple, bool]


MAX_WEAK_SIGMA_FACTOR = 100.0
"""A loop closure's least constrained direction is at most this many times wider than its
best (``loop_information``)."""


def loop_covariance(options, information: Optional[np.ndarray], later_yaw: float) -> np.ndarray:
    """The (3, 3) covariance of a loop closure measured in the later keyframe's frame (where
    GTSAM's between factor reads its error): ``loop_sigma_xy_m`` along the direction the match
    constrains best and ``loop_sigma_xy_m / sqrt(share)`` across it, ``share`` the weaker
    direction's share of the stronger one's information (a corridor passed again: almost 0
    along it), the world frame's x, y turned into the later keyframe's (``later_yaw``);
    ``loop_sigma_yaw_rad`` in yaw. Without information, or with ``loop_information`` off, or
    an information matrix that constrains nothing: ``loop_sigma_xy_m`` in x and y."""
    o = options
    cov = np.diag([o.loop_sigma_xy_m**2, o.loop_sigma_xy_m**2, o.loop_sigma_yaw_rad**2])
    if information is None or not o.loop_information:
        return cov
    block = np.asarray(information, np.float64)[:2, :2]
    if not np.all(np.isfinite(block)):
        return cov
    w, v = np.linalg.eigh(0.5 * (block + block.T))  # ascending
    if not w[-1] > 0:
        return cov
    share = max(w[0] / w[-1], MAX_WEAK_SIGMA_FACTOR**-2)
    world = v @ np.diag([o.loop_sigma_xy_m**2 / share, o.loop_sigma_xy_m**2]) @ v.T
    c, s = math.cos(later_yaw), math.sin(later_yaw)
    r = np.array([[c, -s], [s, c]])
    cov[:2, :2] = r.T @ world @ r
    return cov


class PoseGraphOptions(OptionsObject, kind="pose_graph"):
    """The pose graph's options: the Rust ``PoseGraphOptions`` (``[slam.graph]``).

    >>> PoseGraphOptions(loop_min_score=0.6).loop_min_score, PoseGraphOptions().loop_candidates
    (0.6, 2)
    """

    def field_half_side_m(self) -> float:
        """Half-side [m] of a search's likelihood field around the pose searched from (the
        Rust ``PoseGraphOptions::field_half_side_m``, whose size rule ``validate`` applies)."""
        return pose_graph_field_half_side_m(self.to_dict())


class PoseGraph:
    """Keyframe poses and the edges between them; :meth:`optimize` moves the poses.

    The first pose is held where it is (a prior of 1 mm / 0.1 mrad): the graph's frame is the
    first keyframe's frame, as the odometry's is.
    """

    def __init__(self, options: PoseGraphOptions) -> None:
        if gtsam is None:
            raise ConfigError(
                f"[slam] mode = 'graph' needs GTSAM, which is not installed: {INSTALL_HINT}"
            )
        self.options = options
        self._graph = gtsam.NonlinearFactorGraph()
        self._values = gtsam.Values()
        self._poses: List[PoseTuple] = []
        self.edges: List[Edge] = []
        """Every edge as added: (earlier, later, measured (x, y, yaw), sigmas (x, y, yaw),
        robust): the graph in plain numbers (another solver reads it)."""
        self.loop_closures = 0

    def __len__(self) -> int:
        return len(self._poses)

    @property
    def poses(self) -> np.ndarray:
        """(N, 3) the keyframes' poses (x [m], y [m], yaw [rad]) as last estimated."""
        return np.array(self._poses, np.float64).reshape(-1, 3)

    def pose(self, k: int) -> PoseTuple:
        return self._poses[k]

    def add_keyframe(self, step: Sequence[float]) -> int:
        """Adds a keyframe ``step`` (x, y, yaw) from the last one (the local trajectory's
        motion between them), joined to it by a sequential edge whose standard deviations grow
        with the step; the first keyframe's ``step`` is its pose. Returns its index."""
        step = tuple(float(v) for v in step[:3])
        k = len(self._poses)
        if k == 0:
            pose = step
            self._graph.add(
                gtsam.PriorFactorPose2(
                    0,
                    gtsam.Pose2(*pose),
                    gtsam.noiseModel.Diagonal.Sigmas(np.array([1e-3, 1e-3, 1e-4])),
                )
            )
        else:
            o = self.options
            last = self._poses[-1]
            c, s = math.cos(last[2]), math.sin(last[2])
            pose = (
                last[0] + c * step[0] - s * step[1],
                last[1] + s * step[0] + c * step[1],
                last[2] + step[2],
            )
            d = math.hypot(step[0], step[1])
            xy = o.sequential_sigma_xy_m + o.sequential_sigma_per_m * d
            yaw = o.sequential_sigma_yaw_rad + o.sequential_sigma_per_m * (abs(step[2]) + 0.4 * d)
            self._graph.add(
                gtsam.BetweenFactorPose2(
                    k - 1,
                    k,
                    gtsam.Pose2(*step),
                    gtsam.noiseModel.Diagonal.Sigmas(np.array([xy, xy, yaw])),
                )
            )
            self.edges.append((k - 1, k, step, (xy, xy, yaw), False))
        self._values.insert(k, gtsam.Pose2(*pose))
        self._poses.append(pose)
        return k

    def add_loop_closure(
        self,
        earlier: int,
        later: int,
        measured: Sequence[float],
        information: Optional[np.ndarray] = None,
    ) -> None:
        """A loop closure: keyframe ``later`` seen at ``measured`` (x, y, yaw) in keyframe
        ``earlier``'s frame. ``information``: the match's (3, 3) information matrix over the
        later keyframe's world pose (``floorscan_core::match_information``); with
        ``loop_information`` its x, y block shapes the closure's standard deviations (see
        :func:`loop_covariance`)."""
        if not (0 <= earlier < later < len(self._poses)):
            raise ValueError(f"loop closure {earlier} -> {later} outside 0..{len(self._poses)}")
        o = self.options
        measured = tuple(float(v) for v in measured[:3])
        later_world_yaw = self._poses[earlier][2] + measured[2]
        cov = loop_covariance(o, information, later_world_yaw)
        noise = gtsam.noiseModel.Robust.Create(
            gtsam.noiseModel.mEstimator.Cauchy.Create(o.loop_robust_scale),
            gtsam.noiseModel.Gaussian.Covariance(cov),
        )
        self._graph.add(
            gtsam.BetweenFactorPose2(int(earlier), int(later), gtsam.Pose2(*measured), noise)
        )
        sig = tuple(float(v) for v in np.sqrt(np.diag(cov)))
        self.edges.append((int(earlier), int(later), measured, sig, True))
        self.loop_closures += 1

    def optimize(self) -> None:
        """Levenberg-Marquardt from the current estimate; the poses take the result."""
        result = gtsam.LevenbergMarquardtOptimizer(self._graph, self._values).optimize()
        self._values = result
        self._poses = [
            (p.x(), p.y(), p.theta()) for p in (result.atPose2(k) for k in range(len(self._poses)))
        ]

    def error(self) -> float:
        """The graph's cost at the current estimate (half the sum of whitened squared
        residuals, the loss applied)."""
        return float(self._graph.error(self._values))
