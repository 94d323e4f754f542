"""Local scan matching in the pipeline (``[slam]``'s local mode, the default where odometry
is given): each frame's scan is matched against the scans kept so far before it is inserted
into the maps, and the match is fused with odometry by their covariances.

The matcher is the drive loop's (:class:`~floorscan.mapping.scan_matcher.ScanMatcher`): a
correlative search of a window around the prediction, scored on a likelihood field of the
boundary points stored so far, then an extended Kalman filter that fuses the match (its
information: the curvature of the field over x, y, yaw) with the odometry prediction (its
covariance grown with each wheel's travel) and estimates odometry's turn scale and heading
drift. The prediction for a frame is the last corrected pose moved by odometry's increment
since: the correction (REP 105's ``map -> odom``, :attr:`PoseCorrection.map_from_odom`)
carries over to the frames that are not matched.

What a camera's scan can constrain, and what it cannot: the scan is the floor's boundary
within about 3 m over the camera's field of view (about 60 degrees), so a match fixes the pose
only across the surfaces it sees. A wall seen face on fixes the distance to it and the
heading, not the position along it; a long plain corridor seen down its length fixes the
position across it and the heading, never along it (the match's information is zero along
the corridor and the filter keeps odometry's distance there); a view across an open room, or
one or two desk legs, gives fewer than ``min_points`` points and is not matched at all (the
pose is odometry's, moved by the last correction). What was never seen before cannot be
corrected, and errors accumulated where nothing constrains them stay (no loop closure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..formats.trajectory import Trajectory, compose, inverse  # noqa: F401 (inverse re-exported)
from ..mapping.scan_matcher import ScanMatcher, ScanMatcherOptions, boundary_points_robot
from ..ranging.scan import Scan

PoseTuple = Tuple[float, float, float]


@dataclass
class MatchCounts:
    """Frames by what the matcher did with them."""

    matched: int = 0
    """Matched and fused with odometry."""
    not_matched: int = 0
    """Odometry's prediction kept: too few points, a score below ``min_score``, nothing stored
    near yet, or the innovation gate."""

    @property
    def frames(self) -> int:
        return self.matched + self.not_matched

    def as_dict(self) -> Dict[str, int]:
        return {"frames_matched": self.matched, "frames_not_matched": self.not_matched}


class PoseCorrection:
    """Odometry poses in, corrected poses out, one frame at a time.

    ``options``: the matcher's (a :class:`ScanMatcherOptions`, or a dict of its fields, as
    ``[slam.matcher]``); ``robot_from_camera``: the camera ground frame on the robot (x [m],
    y [m], yaw [rad]). Keeps both trajectories (:attr:`odometry`, :attr:`corrected`).
    """

    def __init__(self, options=None, *, robot_from_camera: PoseTuple = (0.0, 0.0, 0.0)) -> None:
        if options is None:
            options = ScanMatcherOptions()
        elif isinstance(options, dict):
            options = ScanMatcherOptions.from_dict(options)
        self.options = options
        self.robot_from_camera = tuple(float(v) for v in robot_from_camera)
        self.matcher: Optional[ScanMatcher] = None
        self.map_from_odom: PoseTuple = (0.0, 0.0, 0.0)
        self.counts = MatchCounts()
        self._odometry: List[Tuple[float, float, float, float]] = []
        self._corrected: List[Tuple[float, float, float, float]] = []

    def correct(self, scan: Scan, odometry_pose, *, timestamp: float) -> PoseTuple:
        """The corrected ``world_from_robot`` of the frame whose scan is ``scan`` and whose
        odometry pose is ``odometry_pose``; stores the scan's new points at it."""
        points = boundary_points_robot(scan, self.robot_from_camera)
        return self.correct_points(points, odometry_pose, timestamp=timestamp)

    def correct_points(self, points_robot, odometry_pose, *, timestamp: float) -> PoseTuple:
        """As :meth:`correct`, for any range sensor's points: ``points_robot`` (N, 2) [m] in
        the robot frame (a laser's beam ends)."""
        odo = tuple(float(v) for v in odometry_pose[:3])
        if self.matcher is None:
            # the matcher's map is centred on the first pose (its size_m square)
            self.matcher = ScanMatcher(self.options, center=odo[:2])
        prior = compose(self.map_from_odom, odo)
        result = self.matcher.correct(np.asarray(points_robot, np.float64).reshape(-1, 2), prior)
        pose = tuple(float(v) for v in result.pose)
        if result.accepted:
            self.counts.matched += 1
        else:
            self.counts.not_matched += 1
        self.map_from_odom = compose(pose, inverse(odo))
        self._odometry.append((float(timestamp), *odo))
        self._corrected.append((float(timestamp), *pose))
        return pose

    @property
    def odometry(self) -> Trajectory:
        """The odometry poses of the frames corrected (a TUM-ready trajectory)."""
        return Trajectory.from_increasing(self._odometry)

    @property
    def corrected(self) -> Trajectory:
        """The corrected poses (a TUM-ready trajectory)."""
        return Trajectory.from_increasing(self._corrected)

    def summary(self) -> Dict[str, object]:
        """Counts and the final correction (``map -> odom``: metres and radians)."""
        dx, dy, dyaw = self.map_from_odom
        return {
            **self.counts.as_dict(),
            "final_correction_m": math.hypot(dx, dy),
            "final_correction_rad": math.remainder(dyaw, 2 * math.pi),
            "odometry_calibration": {
                "turn_scale_error": self.matcher.calibration[0] if self.matcher else 0.0,
                "drift_rad_per_m": self.matcher.calibration[1] if self.matcher else 0.0,
            },
        }
