"""The whole system as the paper's robot ran it: frames and odometry in, scans and occupancy
maps out. :class:`Mapper` is the per-frame core (ranger + global map + local map);
:func:`run` drives it over a frame source and writes every output through
:class:`~floorscan.pipeline.outputs.RunOutputs`.
"""

from __future__ import annotations

import signal
import time
from dataclasses import dataclass, field
from typing import Dict, Optional, Tuple

import numpy as np

from .._signals import StopRequest
from ..errors import ConfigError, FloorscanError, ImageError, OutOfBoundsError
from ..formats.image_io import as_grey
from ..formats.trajectory import Pose2, Trajectory, compose
from ..mapping.grid import OccupancyGrid
from ..mapping.local_map import LocalMap
from ..ranging.appearance import AppearanceRanger
from ..ranging.auto_threshold import MIN_AUTO_THRESHOLD, auto_threshold
from ..ranging.fused import FusedRanger
from ..ranging.ground_table import GroundTable
from ..ranging.parallax import ParallaxRanger
from ..ranging.ranger import VisualRanger
from ..ranging.scan import ColumnStatus, Scan
from .config import Config
from .config_tables import SHARED_WITH_RANGER
from .driven_floor import driven_floor_for
from .pose_correction import PoseCorrection
from .sources import FrameSource

PoseTuple = Tuple[float, float, float]


RANGER_KINDS = ("edge", "appearance", "fused")


def ranger_from_config(table: GroundTable, cfg: Config, **overrides):
    """The range sensor of ``cfg.ranger.kind`` (edge, appearance or fused) for ``table``;
    ``overrides`` replace options shared by the rangers (``columns``, ``start``,
    ``max_range_m``) or the edge ranger's (``threshold``...)."""
    r, a = cfg.ranger, cfg.appearance
    if r.kind not in RANGER_KINDS:
        raise ConfigError(
            f"invalid ranger.kind {r.kind!r}: expected one of {', '.join(RANGER_KINDS)}"
        )
    edge_options = {**r.options(), **overrides}
    shared = {k: edge_options[k] for k in SHARED_WITH_RANGER}

    def edge() -> VisualRanger:
        return VisualRanger(table, **edge_options)

    def appearance() -> AppearanceRanger:
        return AppearanceRanger(table, **a.options(), **shared)

    if r.kind == "edge":
        return edge()
    if r.kind == "appearance":
        return appearance()
    return FusedRanger(
        edge(),
        appearance(),
        snap_rows=a.snap_rows,
        snap_fraction=a.snap_fraction,
        texture_share=a.texture_share,
    )


def parallax_for(ranger, cfg: Config) -> Optional[ParallaxRanger]:
    """The floor-parallax cue over ``ranger`` when ``[parallax] enabled`` (the edge ranger
    only: ConfigError for another kind)."""
    if not cfg.parallax.enabled:
        return None
    if not isinstance(ranger, VisualRanger):
        raise ConfigError(
            f'[parallax] enabled needs the edge ranger (ranger.kind = "edge"), not '
            f"{cfg.ranger.kind!r}"
        )
    return ParallaxRanger(
        ranger, **{k: v for k, v in cfg.parallax.options().items() if k != "enabled"}
    )


def grid_kwargs(cfg: Config) -> Dict[str, object]:
    """The keyword options of :class:`OccupancyGrid` and :class:`LocalMap` from ``[grid]`` and
    ``[sensors]``."""
    return {**cfg.grid.options(), **cfg.sensors.options()}


def local_map_kwargs(cfg: Config) -> Dict[str, object]:
    """The keyword options of :class:`LocalMap`: ``[grid]`` and ``[sensors]``, then
    ``[local_map]`` (its size and its own visual evidence, which replaces
    ``[sensors.visual]``)."""
    return {**grid_kwargs(cfg), **cfg.local_map.options()}


@dataclass
class StageTimes:
    """Wall time per stage [s], summed over the run."""

    decode_s: float = 0.0
    ranging_s: float = 0.0
    matching_s: float = 0.0
    mapping_s: float = 0.0
    output_s: float = 0.0

    def as_dict(self) -> Dict[str, float]:
        return {k: round(v, 6) for k, v in self.__dict__.items()}


class Mapper:
    """Ranger plus a growing global map (world frame) and a robot-centred local map.

    ``robot_from_camera``: (x [m], y [m], yaw [rad]) of the camera ground frame on the robot.
    Poses passed to :meth:`process` are ``world_from_robot`` (x, y, yaw) from odometry; with
    ``None`` (no odometry), only the local map is updated, as if the robot stood still. In
    ``[slam]``'s local mode (the default) each odometry pose is corrected by matching the
    scan against the scans kept so far (:class:`~floorscan.pipeline.pose_correction.
    PoseCorrection`, :attr:`slam`) before the scan is inserted; off: odometry as it is.
    """

    def __init__(
        self, table: GroundTable, cfg: Config, *, robot_from_camera: PoseTuple = (0.0, 0.0, 0.0)
    ) -> None:
        self.cfg = cfg
        self.ranger = ranger_from_config(table, cfg)
        # the appearance ranger's refresh from floor driven over (appearance / fused rangers)
        self.driven_floor = driven_floor_for(self.ranger)
        self.threshold_pending = cfg.ranger.auto_threshold
        self.threshold = cfg.ranger.threshold
        self.texture_noise: Optional[float] = None
        self.robot_from_camera = tuple(float(v) for v in robot_from_camera)
        kw = grid_kwargs(cfg)
        # The global map keeps its unclamped evidence too, so runs merge exactly (evidence.py).
        self.global_map = OccupancyGrid(keep_evidence=True, **kw)
        self.local_map = LocalMap(**local_map_kwargs(cfg))
        self.parallax: Optional[ParallaxRanger] = parallax_for(self.ranger, cfg)
        self.slam: Optional[PoseCorrection] = None
        if cfg.slam.mode == "graph":
            raise ConfigError(
                "[slam] mode = 'graph' is floorscan map-log's (laser logs) so far: camera runs "
                "take 'local' or 'off'"
            )
        if cfg.slam.mode == "local":
            self.slam = PoseCorrection(
                cfg.slam.options()["matcher"], robot_from_camera=self.robot_from_camera
            )
        self.times = StageTimes()
        self.frames = 0
        self.points = 0
        self.last_pose: Optional[PoseTuple] = None
        """The pose the last frame was inserted at (corrected when ``slam`` is on)."""

    def process(self, image: np.ndarray, *, timestamp: float, pose: Optional[PoseTuple]) -> Scan:
        if self.threshold_pending:
            self._set_auto_threshold(image)
        t0 = time.perf_counter()
        if self.parallax is not None:
            camera = None if pose is None else compose(pose, self.robot_from_camera)
            scan = self.parallax.scan(image, timestamp=timestamp, world_from_camera=camera)
        else:
            scan = self.ranger.scan(image, timestamp=timestamp)
        t1 = time.perf_counter()
        if pose is not None and self.slam is not None:
            pose = self.slam.correct(scan, pose, timestamp=timestamp)
        t2 = time.perf_counter()
        if pose is not None and self.driven_floor is not None:
            self.driven_floor.update(pose, self.robot_from_camera, timestamp)
        self.last_pose = pose
        t3 = time.perf_counter()
        if pose is not None:
            self.global_map.insert_scan(scan, pose=pose, mount=self.robot_from_camera)
            self.local_map.insert_scan(scan, pose=pose, mount=self.robot_from_camera)
        else:
            self.local_map.insert_scan(scan, pose=(0.0, 0.0, 0.0), mount=self.robot_from_camera)
        t4 = time.perf_counter()
        self.times.ranging_s += (t1 - t0) + (t3 - t2)
        self.times.matching_s += t2 - t1
        self.times.mapping_s += t4 - t3
        self.frames += 1
        self.points += int(np.count_nonzero(scan.status_codes == ColumnStatus.BOUNDARY))
        return scan

    def _set_auto_threshold(self, image: np.ndarray) -> None:
        """The threshold from the first frame's texture noise (ranger.auto_threshold)."""
        r = self.cfg.ranger
        t, self.texture_noise = auto_threshold(
            [as_grey(image)],
            half_width=r.half_width_px,
            columns=self.ranger.columns,
            k=r.auto_threshold_k,
            bottom_margin=r.start.get("bottom_margin", 0),
        )
        self.threshold = max(t, MIN_AUTO_THRESHOLD)
        cfg = self.cfg.with_overrides(
            {"ranger.threshold": self.threshold, "ranger.auto_threshold": False}
        )
        self.ranger = ranger_from_config(self.ranger.table, cfg)
        self.driven_floor = driven_floor_for(self.ranger)
        self.parallax = parallax_for(self.ranger, cfg)
        self.threshold_pending = False


@dataclass
class RunStats:
    frames_in: int = 0
    frames_mapped: int = 0
    skipped_unreadable: int = 0
    skipped_no_odometry: int = 0
    skipped_wrong_size: int = 0
    skipped_out_of_map: int = 0
    dropped_live: int = 0
    boundary_points: int = 0
    interrupted: bool = False
    signal: Optional[int] = None
    error: Optional[str] = None
    wall_s: float = 0.0
    skip_reasons: Dict[str, str] = field(default_factory=dict)

    def as_dict(self) -> Dict[str, object]:
        d = dict(self.__dict__)
        d["skip_reasons"] = dict(list(self.skip_reasons.items())[:20])
        return d


def match_pose(odometry: Optional[Trajectory], t: float) -> Tuple[Optional[Pose2], bool]:
    """(pose, ok): the interpolated pose at ``t``; ok is False when odometry exists but does
    not cover ``t`` (the frame is skipped and counted, never guessed)."""
    if odometry is None:
        return None, True
    p = odometry.pose_at(t)
    return p, p is not None


def run(
    source: FrameSource,
    mapper: Mapper,
    outputs,
    *,
    strict: bool = False,
    progress=None,
) -> RunStats:
    """Runs the mapper over every frame of ``source``; outputs are always finalised, on
    SIGINT (Ctrl-C), SIGTERM, SIGHUP and on error too, so the map built so far is never lost.
    A signal stops the run after the current frame; see :mod:`floorscan._signals`."""
    stats = RunStats()
    start = time.perf_counter()
    shape = (mapper.ranger.table.image_height, mapper.ranger.table.image_width)
    stop = StopRequest()
    source.bind_stop(stop)
    with stop.installed():
        try:
            with stop.loop():
                _frame_loop(source, mapper, outputs, stats, shape, stop, strict, progress)
        except KeyboardInterrupt as e:
            stats.interrupted = True
            stats.signal = getattr(e, "signum", int(signal.SIGINT))
        except FloorscanError as e:
            stats.error = str(e)
            raise
        finally:
            if progress is not None:
                progress.close()
            source.close()
            if stop.requested:
                stats.interrupted = True
                stats.signal = stats.signal or stop.signum
            stats.dropped_live = source.dropped
            stats.boundary_points = mapper.points
            stats.wall_s = time.perf_counter() - start
            outputs.finish(mapper, stats)
    return stats


def _frame_loop(source, mapper, outputs, stats, shape, stop, strict, progress) -> None:
    frames = iter(source)
    try:
        _frames_until_stop(frames, source, mapper, outputs, stats, shape, stop, strict, progress)
    finally:
        # closed here, inside the loop's signal handling, not when the garbage collector
        # finalises it: a second signal during its clean-up then stops the run as it should,
        # where in a finaliser it was printed as an ignored exception
        close = getattr(frames, "close", None)
        if close is not None:
            close()


def _frames_until_stop(frames, source, mapper, outputs, stats, shape, stop, strict, progress):
    while not stop.requested:
        t_dec = time.perf_counter()
        frame = next(frames, None)
        mapper.times.decode_s += time.perf_counter() - t_dec
        if frame is None:
            break
        stats.frames_in += 1
        if frame.image is None:
            if strict:
                raise ImageError(f"frame {frame.index} (t={frame.timestamp}): {frame.error}")
            stats.skipped_unreadable += 1
            stats.skip_reasons.setdefault(f"frame {frame.index}", frame.error or "unreadable")
            continue
        if frame.image.shape[:2] != shape:
            msg = f"frame {frame.index} is {frame.image.shape[1]}x{frame.image.shape[0]}, the calibration is for {shape[1]}x{shape[0]}"
            if strict:
                raise ImageError(msg)
            stats.skipped_wrong_size += 1
            stats.skip_reasons.setdefault(f"frame {frame.index}", msg)
            continue
        pose, ok = match_pose(source.odometry, frame.timestamp)
        if not ok:
            if strict:
                raise FloorscanError(
                    f"frame {frame.index} at t={frame.timestamp} is outside the odometry's time range"
                )
            stats.skipped_no_odometry += 1
            continue
        pose_t = pose.as_tuple() if pose is not None else None
        try:
            scan = mapper.process(frame.image, timestamp=frame.timestamp, pose=pose_t)
        except OutOfBoundsError as e:
            # A pose outside the map's limits ([map] max_cells): wrong odometry, not a map.
            if strict:
                raise
            stats.skipped_out_of_map += 1
            stats.skip_reasons.setdefault(f"frame {frame.index}", str(e))
            continue
        stats.frames_mapped += 1
        t_out = time.perf_counter()
        outputs.on_frame(frame, scan, pose_t, mapper)
        mapper.times.output_s += time.perf_counter() - t_out
        if progress is not None:
            progress.update(
                stats.frames_in,
                skipped=stats.frames_in - stats.frames_mapped,
                dropped=source.dropped,
            )
