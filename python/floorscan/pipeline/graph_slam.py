"""Loop closure over a pose graph (``[slam] mode = "graph"``; ``floorscan map-log``'s default
with ``--poses odometry``), Cartographer's shape at a laser log's scale:

1. **Local trajectory**: each scan is matched (the correlative search of
   ``floorscan_core::correlative_search``, ``[slam.graph] search_*``) against a rolling submap,
   the points of the latest ``submap_keyframes`` keyframes, from odometry's prediction (the
   last pose moved by odometry's increment); a match below ``min_score`` keeps the prediction.
   A scan becomes a keyframe after ``keyframe_distance_m`` or ``keyframe_rotation_rad``. The
   submap forgets: unlike the local mode's persistent map, an error made here is not frozen
   into the map a later pass snaps to; the graph undoes it.
2. **Loop closures**: every ``loop_every_keyframes``-th keyframe is matched, over a wider
   window (``loop_search_*``), against the keyframes at least ``loop_min_travel_m`` of travel
   behind it whose estimated positions lie within ``loop_search_radius_m`` (the nearest
   ``loop_candidates``, each with ``loop_neighbours`` keyframes either side, placed at the
   graph's current estimate); a match scoring ``loop_min_score`` is a loop closure, weighed by
   what the match constrains (``loop_information``: a corridor passed again closes across
   it, hardly along it).
3. **The graph** (:class:`~floorscan.mapping.pose_graph.PoseGraph`) is optimised after each
   keyframe that closed a loop, so the next search starts from the corrected estimate, and
   once more at the end. Every scan's pose is its keyframe's optimised pose moved by the local
   trajectory's motion since that keyframe.

Each search's likelihood field covers only the square the scan can reach from the pose
searched from (``PoseGraphOptions.field_half_side_m``), so its size is bounded by the options.
"""

from __future__ import annotations

import math
from typing import Dict, List, Optional, Sequence, Tuple

import cv2
import numpy as np

from .._native.mapping import FIELD_REUSE_M, correlative_search, match_information
from ..formats.trajectory import compose, inverse, relative
from ..mapping.pose_graph import PoseGraph, PoseGraphOptions

PoseTuple = Tuple[float, float, float]

FIELD_SIGMAS = 3.0
"""The likelihood field is 0 beyond this many widths from every point."""


def to_world(pose: Sequence[float], points: np.ndarray) -> np.ndarray:
    """(N, 2) points of a frame at ``pose`` (x, y, yaw) in the world."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.stack(
        [
            pose[0] + c * points[:, 0] - s * points[:, 1],
            pose[1] + s * points[:, 0] + c * points[:, 1],
        ],
        axis=1,
    )


def likelihood_field(
    points_world: np.ndarray,
    center: Sequence[float],
    half_side_m: float,
    cell_m: float,
    sigma_m: float,
) -> Optional[Tuple[np.ndarray, Tuple[float, float]]]:
    """The likelihood field (exp(-d^2 / 2 sigma^2), d the distance to the nearest point; rows
    along y) over the square of half-side ``half_side_m`` around ``center``, and its corner;
    None when no point lies in the square."""
    lo = np.array([center[0] - half_side_m, center[1] - half_side_m])
    n = int(math.ceil(2 * half_side_m / cell_m))
    ij = np.floor((points_world - lo) / cell_m).astype(np.int64)
    inside = (ij >= 0).all(axis=1) & (ij < n).all(axis=1)
    if not inside.any():
        return None
    free = np.full((n, n), 255, np.uint8)
    free[ij[inside, 1], ij[inside, 0]] = 0
    d = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * cell_m
    field = np.exp(-0.5 * (d / sigma_m) ** 2).astype(np.float32)
    field[d > FIELD_SIGMAS * sigma_m] = 0.0
    return np.ascontiguousarray(field), (float(lo[0]), float(lo[1]))


class GraphSlam:
    """Odometry poses and scan points in, one frame at a time; :meth:`finish` gives every
    frame's optimised pose. ``options``: a :class:`PoseGraphOptions` or a dict of its fields
    (``[slam.graph]``)."""

    def __init__(self, options=None) -> None:
        if options is None:
            options = PoseGraphOptions()
        elif isinstance(options, dict):
            options = PoseGraphOptions(**options)
        self.options = options
        self.graph = PoseGraph(options)
        self._local: List[PoseTuple] = []  # each frame's pose on the local trajectory
        self._keyframe_of: List[int] = []  # each frame's keyframe (the last at or before it)
        self._keyframe_frames: List[int] = []  # each keyframe's frame
        self._keyframe_points: List[np.ndarray] = []  # (N, 2) in the keyframe's frame
        self._travel: List[float] = []  # local trajectory's length at each keyframe
        self._last_odometry: Optional[PoseTuple] = None
        self._submap: Optional[Tuple[np.ndarray, Tuple[float, float], PoseTuple]] = None
        self.matched = 0
        self.not_matched = 0
        self.recovered = 0
        """Scans placed by the wide yaw search (``recovery_yaw_rad``)."""

    def _usable(self, points_robot) -> np.ndarray:
        o = self.options
        pts = np.asarray(points_robot, np.float64).reshape(-1, 2)
        pts = pts[np.hypot(pts[:, 0], pts[:, 1]) <= o.range_max_m]  # drops NaN too
        if len(pts) > o.max_points:
            pts = pts[np.linspace(0, len(pts) - 1, int(o.max_points)).round().astype(np.int64)]
        return np.ascontiguousarray(pts)

    def _search(self, field, corner, points, prior, xy_m: float, yaw_rad: float, yaw_step=None):
        o = self.options
        step = o.yaw_step_rad if yaw_step is None else yaw_step
        pose, mean, _ = correlative_search(
            field,
            corner,
            o.cell_size_m,
            points,
            tuple(float(v) for v in prior),
            int(round(xy_m / o.cell_size_m)),
            int(round(yaw_rad / step)),
            step,
            1e6,  # no prior: the window bounds the search (a prior of 0.5-1 m did no
            1e6,  # better on the real logs: bench/laser_odometry.py)
        )
        return tuple(float(v) for v in pose), float(mean)

    def add(self, points_robot, odometry_pose) -> PoseTuple:
        """The frame's pose on the local trajectory (matched against the rolling submap)."""
        o = self.options
        odo = tuple(float(v) for v in odometry_pose[:3])
        pts = self._usable(points_robot)
        if self._last_odometry is None:
            pose = odo
        else:
            pose = compose(self._local[-1], compose(inverse(self._last_odometry), odo))
            matched = False
            if len(pts) >= 3 and self._submap_for(pose) is not None:
                field, corner, _ = self._submap
                found, mean = self._search(
                    field, corner, pts, pose, o.search_xy_m, o.search_yaw_rad
                )
                if mean >= o.min_score:
                    pose, matched = found, True
                elif o.recovery_yaw_rad > o.search_yaw_rad:
                    # odometry turned wrong by more than the window: search all turns near
                    found, mean = self._search(
                        field,
                        corner,
                        pts,
                        pose,
                        o.search_xy_m,
                        o.recovery_yaw_rad,
                        2 * o.yaw_step_rad,
                    )
                    if mean >= o.loop_min_score:
                        pose, matched = found, True
                        self.recovered += 1
            self.matched += matched
            self.not_matched += not matched
        self._last_odometry = odo
        self._local.append(pose)
        frame = len(self._local) - 1
        if not self._keyframe_frames or self._is_keyframe(pose):
            self._add_keyframe(frame, pts)
        self._keyframe_of.append(len(self._keyframe_frames) - 1)
        return pose

    def _is_keyframe(self, pose: PoseTuple) -> bool:
        o = self.options
        last = self._local[self._keyframe_frames[-1]]
        return (
            math.hypot(pose[0] - last[0], pose[1] - last[1]) >= o.keyframe_distance_m
            or abs(math.remainder(pose[2] - last[2], 2 * math.pi)) >= o.keyframe_rotation_rad
        )

    def _submap_for(self, pose: PoseTuple):
        """The rolling submap's field around ``pose`` (rebuilt when a keyframe was added or
        the pose left the square it covers); None while it holds no point near."""
        o = self.options
        half = o.field_half_side_m()
        if self._submap is not None:
            c = self._submap[2]
            if max(abs(pose[0] - c[0]), abs(pose[1] - c[1])) <= FIELD_REUSE_M:
                return self._submap
        keys = range(
            max(0, len(self._keyframe_frames) - int(o.submap_keyframes)), len(self._keyframe_frames)
        )
        pts = [
            to_world(self._local[self._keyframe_frames[k]], self._keyframe_points[k]) for k in keys
        ]
        built = (
            likelihood_field(np.concatenate(pts), pose, half, o.cell_size_m, o.sigma_m)
            if pts
            else None
        )
        self._submap = None if built is None else (built[0], built[1], pose)
        return self._submap

    def _add_keyframe(self, frame: int, pts: np.ndarray) -> None:
        o = self.options
        pose = self._local[frame]
        if self._keyframe_frames:
            previous = self._local[self._keyframe_frames[-1]]
            self._travel.append(
                self._travel[-1] + math.hypot(pose[0] - previous[0], pose[1] - previous[1])
            )
            k = self.graph.add_keyframe(relative(previous, pose))
        else:
            self._travel.append(0.0)
            k = self.graph.add_keyframe(pose)
        self._keyframe_frames.append(frame)
        self._keyframe_points.append(pts)
        self._submap = None  # the new keyframe joins the submap
        if k > 0 and k % int(o.loop_every_keyframes) == 0 and len(pts) >= 3:
            if self._close_loops(k):
                self.graph.optimize()

    def _close_loops(self, k: int) -> bool:
        o = self.options
        poses = self.graph.poses
        here = poses[k]
        travel = np.asarray(self._travel)
        dist = np.hypot(poses[:k, 0] - here[0], poses[:k, 1] - here[1])
        eligible = (travel[k] - travel[:k] >= o.loop_min_travel_m) & (
            dist <= o.loop_search_radius_m
        )
        candidates = [int(j) for j in np.argsort(dist) if eligible[j]][: int(o.loop_candidates)]
        closed = False
        for j in candidates:
            near = range(max(0, j - int(o.loop_neighbours)), min(k, j + int(o.loop_neighbours) + 1))
            # keyframes close to k in travel are the local trajectory's, not a loop's
            near = [m for m in near if travel[k] - travel[m] >= o.loop_min_travel_m]
            if not near:
                continue
            pts = np.concatenate([to_world(poses[m], self._keyframe_points[m]) for m in near])
            built = likelihood_field(pts, here, o.field_half_side_m(), o.cell_size_m, o.sigma_m)
            if built is None:
                continue
            found, mean = self._search(
                built[0],
                built[1],
                self._keyframe_points[k],
                here,
                o.loop_search_xy_m,
                o.loop_search_yaw_rad,
            )
            if mean >= o.loop_min_score:
                information = None
                if o.loop_information:  # what the match constrains, and what it does not
                    information = match_information(
                        built[0],
                        built[1],
                        o.cell_size_m,
                        self._keyframe_points[k],
                        found,
                        o.yaw_step_rad,
                    )
                self.graph.add_loop_closure(j, k, relative(poses[j], found), information)
                closed = True
        return closed

    def finish(self) -> np.ndarray:
        """(N, 3) every frame's pose: its keyframe's optimised pose moved by the local
        trajectory's motion since it."""
        if len(self.graph) == 0:
            return np.zeros((0, 3))
        self.graph.optimize()
        keys = self.graph.poses
        out = np.empty((len(self._local), 3))
        for f, (local, k) in enumerate(zip(self._local, self._keyframe_of)):
            kf = self._local[self._keyframe_frames[k]]
            out[f] = compose(tuple(keys[k]), relative(kf, local))
        return out

    @property
    def local_poses(self) -> np.ndarray:
        """(N, 3) every frame's pose on the local trajectory (before the graph)."""
        return np.array(self._local, np.float64).reshape(-1, 3)

    def summary(self) -> Dict[str, object]:
        return {
            "frames_matched": self.matched,
            "frames_not_matched": self.not_matched,
            "frames_recovered": self.recovered,
            "keyframes": len(self.graph),
            "loop_closures": self.graph.loop_closures,
        }
