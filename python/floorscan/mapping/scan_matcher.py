"""Correcting the odometry pose with the robot's own scans: a correlative scan-to-map matcher
(Olson 2009; cartographer's real-time correlative scan matcher, hector_mapping's role).
The drive loop (``floorscan drive``) and the pipeline's local scan matching (``floorscan run``,
``node``, ``fleet``, ``eval``: :mod:`floorscan.pipeline.pose_correction`) share it; its
options are the Rust ``ScanMatcherOptions`` (``[slam.matcher]`` in the config file).

The robot keeps a persistent map of where its scans ended (hit counts on a fixed grid centred
on its start, in the frame its waypoints are given in). Each frame, the scan's end points
(visual boundary points, or laser returns) are tried at every pose of a small window around
the odometry pose (translations on the grid's cells, yaws in fixed steps); each pose scores
the mean of a likelihood field (exp(-d^2 / 2 sigma^2), d the distance to the nearest hit in
the map) at the points, times a prior exp(-(|t| / sigma_t)^2 - (theta / sigma_theta)^2) that
keeps the pose near odometry where the scan does not decide (a corridor's length). The best
pose is kept when enough points score; then the scan's points that the map does not already
explain (no stored hit within ``novelty_m``) join the map at that pose. Storing only what is
new keeps the map as it was first seen: a robot that comes back with drifted odometry matches
the walls as they were, not its own latest, drifted copies of them (which would let the error
stay, as a matcher against its last few frames does).

The pose kept is not the best pose as it is: the match is fused with the odometry
prediction as an extended Kalman filter (``predict``, ``information``, ``fuse``). The
prediction's covariance grows with each wheel's travel; the match's information is the
curvature of the summed field values over (x, y, yaw) at the pose found, so a corridor
corrects across itself and not along, and a narrow view of near walls corrects the heading
little; two more states estimate odometry's systematic errors (turn scale, heading drift per
metre) from the matches, as robots calibrate their odometry, and correct each prediction.
Kept as it was, each frame's match (the best of a flat-topped score) scattered by about
0.015 rad, and the points stored at it turned that scatter into a rotated map of each
unseen room (EVALUATION.md, "Long tours").

The matcher's state (the hit map, the likelihood field kept over part of it, the filter) and
every step of a frame live in the Rust core (``floorscan_core::scan_matcher``, its
``correlative_search``, ``hit_map``, ``match_information`` and ``match_filter``); this class is
its Python face, one call a frame (``correct``).

Odometry's heading error grows with the square root of the distance travelled (wheel noise)
and turns it into metres of position error; matching against walls seen before keeps the
heading, and so the waypoints, where they are. It cannot close large loops (no global search,
no graph): what was never seen stays as odometry leaves it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Dict, Optional, Tuple

import numpy as np

from .._native.mapping import ScanMatcher as _NativeScanMatcher
from ..options import check
from ..ranging.scan import ColumnStatus


def boundary_points_robot(scan, robot_from_camera) -> np.ndarray:
    """The scan's boundary points (N, 2) [m, robot frame]: the camera's ground frame moved by
    ``robot_from_camera`` (x [m], y [m], yaw [rad]). What the matcher matches and stores of a
    visual scan (its columns with no boundary, too close or invalid say nothing of walls)."""
    bnd = np.asarray(scan.status_codes) == int(ColumnStatus.BOUNDARY)  # an int compares fast
    x, y = np.asarray(scan.x)[bnd], np.asarray(scan.y)[bnd]
    m = robot_from_camera
    c, s = math.cos(m[2]), math.sin(m[2])
    return np.stack([m[0] + c * x - s * y, m[1] + s * x + c * y], 1)


class ScanMatcherOptions:
    """The matcher's options: the Rust ``ScanMatcherOptions`` (defaults, docs and rules live
    there, ``crates/floorscan-core/src/mapping/scan_matcher_options.rs``; ``floorscan.options.
    field_docs("scan_matcher")`` reads the docs). Keyword arguments are any of its fields;
    the others take their defaults; a bad one is an :class:`~floorscan.OptionError` naming
    it. Read-only, attribute access; ``replace(**changes)`` makes a changed copy.

    >>> ScanMatcherOptions(size_m=12.0).size_m, ScanMatcherOptions().min_points
    (12.0, 40)
    """

    __slots__ = ("_values",)

    def __init__(self, **options: Any) -> None:
        object.__setattr__(self, "_values", check("scan_matcher", options))

    @classmethod
    def from_dict(cls, values: Dict[str, Any]) -> ScanMatcherOptions:
        """The options of a dict of any of the fields (a config table's ``matcher``)."""
        return cls(**values)

    def __getattr__(self, name: str) -> Any:
        try:
            return object.__getattribute__(self, "_values")[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("ScanMatcherOptions is read-only: use replace(...)")

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ScanMatcherOptions) and self._values == other._values

    def __hash__(self) -> int:
        return hash(tuple(sorted(self._values.items())))

    def __repr__(self) -> str:
        return f"ScanMatcherOptions({self._values!r})"

    def to_dict(self) -> Dict[str, Any]:
        """Every field (the serde form)."""
        return dict(self._values)

    def replace(self, **changes: Any) -> ScanMatcherOptions:
        return ScanMatcherOptions(**{**self._values, **changes})

    @property
    def gate(self) -> float:
        """``rejection_threshold``, inf when unset (no gate)."""
        g = self._values["rejection_threshold"]
        return math.inf if g is None else float(g)


@dataclass(frozen=True)
class MatchResult:
    """``pose``: the corrected world_from_robot (x, y, yaw); ``score``: its mean field value;
    ``accepted``: whether the correction was applied; ``points``: points used."""

    pose: Tuple[float, float, float]
    score: float
    accepted: bool
    points: int

    @classmethod
    def _of(cls, native) -> MatchResult:
        pose, score, accepted, points = native
        return cls(tuple(pose), score, accepted, points)

    def _native(self):
        return (
            tuple(float(v) for v in self.pose[:3]),
            float(self.score),
            bool(self.accepted),
            int(self.points),
        )


def _points(points_robot) -> np.ndarray:
    return np.ascontiguousarray(points_robot, np.float64).reshape(-1, 2)


def _pose(pose) -> Tuple[float, float, float]:
    return tuple(float(v) for v in pose[:3])


class ScanMatcher:
    """The persistent hit map, the correlative search and the filter (see the module's
    docstring); ``center``: the map's centre [m, world frame] (its ``size_m`` square)."""

    def __init__(self, options: Optional[ScanMatcherOptions] = None, *, center=(0.0, 0.0)) -> None:
        options = options if options is not None else ScanMatcherOptions()
        self.options = options
        self._native = _NativeScanMatcher(options.to_dict(), (float(center[0]), float(center[1])))
        self.cell = options.cell_size_m
        self.n = self._native.side
        self.origin_m = self._native.origin_m

    @property
    def hits(self) -> np.ndarray:
        """The hit counts (n, n) uint8 (row 0 = lowest y; a copy)."""
        return self._native.hits

    @property
    def frames(self) -> int:
        """Scans stored so far."""
        return self._native.frames

    @property
    def field(self) -> Optional[Tuple[np.ndarray, int, int]]:
        """The likelihood field kept over part of the map: (values (h, w) float32, i0, j0)
        with (i0, j0) the map's cell of its first (a copy), None before a match made one."""
        return self._native.field

    def field_around(self, x: float, y: float, half_m: float) -> Tuple[np.ndarray, int, int]:
        """A fresh likelihood field over the square of half-side ``half_m`` [m] around
        (``x``, ``y``), cut to the map, as ``field``."""
        return self._native.field_around(float(x), float(y), float(half_m))

    def cover(self, x: float, y: float, half_m: float) -> Tuple[np.ndarray, int, int]:
        """Makes the kept field cover the square of half-side ``half_m`` [m] around (``x``,
        ``y``) (a fresh one 1 m larger when it does not) and returns it, as ``field``."""
        return self._native.cover(float(x), float(y), float(half_m))

    @property
    def covariance(self) -> np.ndarray:
        """The covariance (5, 5) of the state's error: x [m], y [m], yaw [rad], the turn scale
        error, the heading drift [rad/m]."""
        return self._native.covariance

    @covariance.setter
    def covariance(self, value) -> None:
        self._native.covariance = np.ascontiguousarray(value, np.float64).reshape(5, 5)

    @property
    def calibration(self) -> Tuple[float, float]:
        """Odometry's estimated errors: (turn scale error, heading drift [rad/m])."""
        return self._native.calibration

    @calibration.setter
    def calibration(self, value) -> None:
        self._native.calibration = (float(value[0]), float(value[1]))

    @property
    def last_pose(self) -> Optional[Tuple[float, float, float]]:
        """The pose kept last (world_from_robot), None before the first frame."""
        return self._native.last_pose

    @last_pose.setter
    def last_pose(self, value) -> None:
        self._native.last_pose = None if value is None else _pose(value)

    @property
    def last_mahalanobis(self) -> Optional[float]:
        """The last fused match's innovation as a Mahalanobis distance (None before any)."""
        return self._native.last_mahalanobis

    def match(self, points_robot: np.ndarray, prior) -> MatchResult:
        """The best pose for ``points_robot`` (N, 2) [m, robot frame] near ``prior``
        (world_from_robot), refined below a cell; does not change the map. Not accepted (the
        prior kept) before any scan is stored, with fewer than ``min_points`` usable points
        (finite, within ``range_max_m``), or a mean field value below ``min_score``."""
        return MatchResult._of(self._native.match_scan(_points(points_robot), _pose(prior)))

    def insert(self, points_robot: np.ndarray, pose, *, novel_only: bool = False) -> int:
        """Adds the points [m, robot frame] seen from ``pose`` to the map (counts saturate
        at 255); ``novel_only``: only those without a stored hit within ``novelty_m`` (every
        point of the first scan is new). Returns how many were stored."""
        return self._native.insert(_points(points_robot), _pose(pose), bool(novel_only))

    def predict(self, prior):
        """The prediction for the frame whose odometry pose, carried by the last correction,
        is ``prior`` (world_from_robot, the pose kept last composed with odometry's
        increment): the increment's turn corrected by the estimated turn scale error and
        heading drift per metre, the state's covariance grown as an extended Kalman filter
        predicts (each wheel's travel errs by ``odometry_wheel_sigma`` sqrt(|travel|), their
        mean is the distance driven, their difference over the wheelbase the turn).
        Returns the corrected prior."""
        return self._native.predict(_pose(prior))

    def information(self, points_robot: np.ndarray, pose) -> np.ndarray:
        """The information matrix (3, 3) of the scan's match at ``pose``: minus the Hessian of
        the sum of field values (read bilinearly as the search reads them) at the points over
        (x, y, yaw), by central differences of a cell and a yaw step, with its negative
        eigenvalues cut to 0. Each point on a wall adds 1 / sigma_m^2 across it. Zeros before
        a match made a field."""
        return self._native.information(_points(points_robot), _pose(pose))

    def fuse(self, result: MatchResult, prior, information: np.ndarray) -> MatchResult:
        """The accepted match fused with the prediction ``prior`` (``predict`` first) in
        information form: the match's information is ``information`` /
        ``match_variance_scale``; the covariance shrinks accordingly; refused (the
        prediction kept) beyond ``rejection_threshold`` Mahalanobis units."""
        info = np.ascontiguousarray(information, np.float64).reshape(3, 3)
        return MatchResult._of(self._native.fuse(result._native(), _pose(prior), info))

    def correct(self, points_robot: np.ndarray, prior) -> MatchResult:
        """Matches the scan near the prediction from ``prior`` (``predict``), fuses the match
        with it (``fuse``), then stores what the scan shows that the map does not hold yet,
        at the pose kept (the prediction when the match is refused). One call into Rust."""
        return MatchResult._of(self._native.correct(_points(points_robot), _pose(prior)))
