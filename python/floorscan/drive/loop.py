"""The closed loop in the simulator: sense (the camera through the ranger, or an ideal laser),
localise (scan matching against the robot's own map), map (the avoidance map, in the
odometry frame), plan (costmap with inflation, navigation function, dynamic window), act (the
simulator's differential drive with odometry noise), and judge (contact between the robot's
footprint and any solid, from truth the robot never sees).

Frames as REP 105 has them: the avoidance map and the planner live in the odometry frame,
which moves smoothly with the wheels (what the robot saw a moment ago stays where it saw it);
scan matching estimates ``map_from_odom``, the correction that puts odometry into the world
frame the waypoints are given in, and the goal is carried into the odometry frame through it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, List, Optional, Sequence, Tuple

import numpy as np

from ..calibration import calibrate
from ..errors import OptionError
from ..mapping.scan_matcher import ScanMatcher, ScanMatcherOptions, boundary_points_robot
from ..options import check, choices, defaults
from ..pipeline.config import Config
from ..pipeline.driven_floor import driven_floor_for
from ..pipeline.mapper import parallax_for, ranger_from_config
from ..sim import Camera, Robot, render_calibration, render_image
from .avoidance_map import AvoidanceMap, AvoidanceMapOptions
from .costmap import CostmapOptions, inflate, navigation_function
from .dwa import DwaOptions, choose_velocity
from .result import DriveResult
from .sensor_model import VisualSensorModel
from .solids import Solids

if TYPE_CHECKING:
    from .result import DriveResult

SENSORS = choices("drive_run", "sensor")
"""The range sensors a drive takes (the core's ``DriveSensor``)."""
TABLES = choices("drive_run", "table")
"""The ground tables a drive takes (the core's ``DriveTable``)."""
_RUN = defaults("drive_run")
"""The defaults of the drive's own options: the core's ``DriveRunOptions``."""


@dataclass(frozen=True)
class DriveOptions:
    """Options of :func:`drive`: the core's ``DriveRunOptions`` (defaults, rules and reasons
    in ``crates/floorscan-core/src/navigation/drive_run_options.rs``;
    ``floorscan.options.field_docs("drive_run")``): ``speed_m_s``, ``seconds``, ``seed``,
    ``sensor`` (``"camera"``, the product, or ``"laser"``, an ideal 2-D laser, the anchor),
    ``table`` (``"calibrated"`` from the simulated pattern, or ``"exact"``), ``columns``,
    ``ranger`` (``"edge"``, ``"appearance"``, ``"fused"``: a ``config`` given to :func:`drive`
    supplies the rangers' options, this their kind), ``mid_contrast`` and ``mid_range_m`` (the
    edge ranger's band for the drive; ``mid_range_m`` None leaves the ranger's options as they
    are), ``goal_tolerance_m``, ``waypoint_timeout_s``, ``laser_fov_rad``, ``laser_range_m``,
    ``laser_beams``, ``replan_every``, ``keep_frames``, ``bump_backup_m``, ``scan_matching``;
    a bad one is an :class:`OptionError` naming it. Then the components' own options objects:
    ``matcher``, ``dwa`` (its ``max_speed_m_s`` is ``speed_m_s``), ``map``, ``costmap``,
    ``model``.
    """

    speed_m_s: float = _RUN["speed_m_s"]
    seconds: float = _RUN["seconds"]
    seed: int = _RUN["seed"]
    sensor: str = _RUN["sensor"]
    table: str = _RUN["table"]
    columns: int = _RUN["columns"]
    ranger: str = _RUN["ranger"]
    mid_contrast: float = _RUN["mid_contrast"]
    mid_range_m: Optional[Tuple[float, float]] = tuple(_RUN["mid_range_m"])
    goal_tolerance_m: float = _RUN["goal_tolerance_m"]
    waypoint_timeout_s: float = _RUN["waypoint_timeout_s"]
    laser_fov_rad: float = _RUN["laser_fov_rad"]
    laser_range_m: float = _RUN["laser_range_m"]
    laser_beams: int = _RUN["laser_beams"]
    replan_every: int = _RUN["replan_every"]
    keep_frames: int = _RUN["keep_frames"]
    bump_backup_m: float = _RUN["bump_backup_m"]
    scan_matching: bool = _RUN["scan_matching"]
    matcher: ScanMatcherOptions = field(default_factory=ScanMatcherOptions)
    dwa: DwaOptions = field(default_factory=DwaOptions)
    map: AvoidanceMapOptions = field(default_factory=AvoidanceMapOptions)
    costmap: CostmapOptions = field(default_factory=CostmapOptions)
    model: VisualSensorModel = field(default_factory=VisualSensorModel)

    def __post_init__(self) -> None:
        own = {name: getattr(self, name) for name in _RUN}
        if own["mid_range_m"] is not None:
            own["mid_range_m"] = list(own["mid_range_m"])
        check("drive_run", own)  # every rule is the core's


@dataclass
class DriveRecord:
    """What happened: per frame ``times_s``, true ``poses``, the robot's world-frame pose
    ``estimates`` and its raw ``odometry`` (N, 3),
    commands (N, 2) and clearance (N,) [m]; contact events; waypoint outcomes; keyframes."""

    times_s: List[float] = field(default_factory=list)
    poses: List[Sequence[float]] = field(default_factory=list)
    odometry: List[Sequence[float]] = field(default_factory=list)
    estimates: List[Sequence[float]] = field(default_factory=list)
    commands: List[Sequence[float]] = field(default_factory=list)
    clearance_m: List[float] = field(default_factory=list)
    contacts: List[dict] = field(default_factory=list)
    waypoints: List[dict] = field(default_factory=list)
    frames: List[tuple] = field(default_factory=list)
    step_s: List[float] = field(default_factory=list)
    plan_s: List[float] = field(default_factory=list)
    stopped_by_signal: Optional[int] = None
    """The signal that stopped the drive early (see ``stop`` of :func:`drive`), or None."""


BACKUP_SPEED_M_S = 0.1
"""The speed [m/s] the robot reverses at after a bump (blind: no camera looks back)."""

BUMPER_SEGMENTS = 8
"""The bumper ring's segments (an iRobot Create's has 6 light-bumper fields, a Kobuki's 3
switches in front): a contact is known to the robot as its segment's central bearing."""


def bumper_segment(pose, contact) -> float:
    """The central bearing [rad, robot frame] of the bumper segment that touches ``contact``
    (x, y) [m] with the robot at ``pose`` (x, y, yaw)."""
    b = math.atan2(contact[1] - pose[1], contact[0] - pose[0]) - pose[2]
    width = 2 * math.pi / BUMPER_SEGMENTS
    return math.remainder(round(b / width) * width, 2 * math.pi)


def drive_ranger(table, options: DriveOptions, config: Optional[Config] = None):
    """The drive's range sensor for ``table``: the kind ``options.ranger`` with the options of
    ``config``'s ``[ranger]`` (and ``[appearance]``) tables, on ``options.columns`` columns,
    the edge ranger's contrast band ``options.mid_contrast`` over ``options.mid_range_m``
    unless the configuration sets a band of its own."""
    cfg = (config or Config()).with_overrides({"ranger.kind": options.ranger})
    band = {}
    near, far = cfg.ranger.options()["mid_range_m"]
    if options.mid_range_m is not None and near >= far:  # the configuration sets no band
        band = {"mid_contrast": options.mid_contrast, "mid_range_m": list(options.mid_range_m)}
    return ranger_from_config(table, cfg, columns=int(options.columns), **band)


def _wrap(angle: float) -> float:
    """The angle in [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def _compose(a, b):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], _wrap(a[2] + b[2]))


def _inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], _wrap(-a[2]))


def _between(a, b):
    """a^-1 * b."""
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + s * dy, -s * dx + c * dy, _wrap(b[2] - a[2]))


def make_table(camera, kind: str):
    """The ranger's ground table: the camera's exact one or calibrated from the simulated
    pattern of dark lines (as ``floorscan demo``), with the calibration's error bars."""
    if kind == "exact":
        return camera.ground_table(spacing_px=4, max_range_m=10.0)
    import tempfile
    from pathlib import Path

    image, pattern = render_calibration(camera, kind="lines")
    with tempfile.TemporaryDirectory() as d:
        p = pattern.save(Path(d) / "pattern.toml")
        table, _ = calibrate(image, p, extrapolate=True)
    return table


class Stepper:
    """Advances the simulated robot by one control period with the simulator's kinematics
    and odometry noise (floorscan.sim.Robot)."""

    def __init__(self, frame_rate_hz: float, seed: int) -> None:
        self.dt = 1.0 / frame_rate_hz
        # 5 samples per period for contact checks along the motion
        self.robot = Robot(frame_rate_hz=5 * frame_rate_hz, speed_mps=3.0, turn_rate_radps=10.0)
        self.seed = int(seed)

    def step(self, pose, v: float, w: float, k: int):
        """(true poses along the period (M, 3), odometry increment robot_before_from_after)."""
        tr = self.robot.drive(
            start=pose,
            seconds=self.dt,
            commands=[[self.dt, v, w]],
            seed=self.seed * 1_000_003 + k,
        )
        odo = tr.odometry
        return tr.poses, _between(tuple(odo[0]), tuple(odo[-1]))


def with_drive_tables(options: DriveOptions, config: Config) -> DriveOptions:
    """``options`` with the avoidance map, the sensor model, the costmap and the planner of
    ``config``'s ``[drive]`` table (``[drive.avoidance_map]``, ``[drive.sensor_model]``,
    ``[drive.costmap]``, ``[drive.dwa]``; the planner's top speed stays ``--speed``)."""
    tables = config.drive.options()
    return replace(
        options,
        map=AvoidanceMapOptions(**tables["avoidance_map"]),
        model=VisualSensorModel(**tables["sensor_model"]),
        costmap=CostmapOptions(**tables["costmap"]),
        dwa=DwaOptions(**tables["dwa"]),
    )


def drive(
    world,
    options: DriveOptions = DriveOptions(),
    *,
    camera=None,
    waypoints=None,
    changes=None,
    table=None,
    config: Optional[Config] = None,
    stop=None,
) -> DriveResult:
    """Drives the world's tour once (or ``waypoints`` (K, 2) [m, world frame]) in closed loop.

    ``changes``: optional list of (time [s], World) switching the world the robot moves in
    (a moved or removed obstacle); contact and the laser always use the current one.
    ``table``: a ready ground table (skips calibration). ``config``: a
    :class:`~floorscan.pipeline.config.Config` whose ``[ranger]`` (and ``[appearance]``)
    tables make the range sensor, as for ``floorscan run`` (its ``columns`` give way to
    ``options.columns``, its ``kind`` to ``options.ranger``), and whose ``[drive]`` table gives
    the avoidance map and the sensor model (``options.map`` and ``options.model`` give way). ``stop``: an object whose
    ``requested`` turns true to end the drive after the current frame (a
    ``floorscan._signals.StopRequest``: ``floorscan drive`` stops on SIGINT, SIGTERM or
    SIGHUP and still writes its outputs); its ``signum`` is recorded. Returns a
    :class:`DriveResult`.
    """
    o = options if config is None else with_drive_tables(options, config)
    camera = camera or Camera()
    tour = np.asarray(world.tour if waypoints is None else waypoints, np.float64).reshape(-1, 2)
    if len(tour) == 0:
        raise OptionError("the world has no tour and no waypoints were given")
    frame_rate = 10.0
    stepper = Stepper(frame_rate, o.seed)
    dt = stepper.dt
    radius = o.costmap.robot_radius_m
    schedule = sorted(changes or [], key=lambda c: c[0])
    current = world
    solids = Solids.of_world(current)
    mount = tuple(camera.robot_from_camera)
    ranger = driven = cue = None
    if o.sensor == "camera":
        table = table if table is not None else make_table(camera, o.table)
        ranger = drive_ranger(table, o, config)
        # appearance / fused rangers: refreshed from the floor the robot drives over
        driven = driven_floor_for(ranger)
        # the configuration's [parallax]: the edge ranger's boundaries checked against the
        # motion since an earlier frame (odometry), floor's own edges scanned past
        cue = parallax_for(ranger, (config or Config()).with_overrides({"ranger.kind": o.ranger}))
    angles = np.linspace(-o.laser_fov_rad / 2, o.laser_fov_rad / 2, int(o.laser_beams))
    true_pose = tuple(world.start)
    # odometry (its frame starts at the true start pose) and the correction into the world
    # frame that scan matching estimates (REP 105's map -> odom)
    odo_pose = tuple(world.start)
    map_from_odom = (0.0, 0.0, 0.0)
    est_pose = odo_pose
    matcher = ScanMatcher(o.matcher, center=odo_pose[:2]) if o.scan_matching else None
    map_options = o.map
    if o.sensor == "laser":  # the laser's evidence is read as it is (no visual calibration)
        map_options = o.map.replace(
            probability_scale=1.0, probability_offset=0.0, probability_knots=None
        )
    amap = AvoidanceMap(map_options, center=odo_pose[:2])
    dwa = o.dwa.replace(max_speed_m_s=o.speed_m_s)
    rec = DriveRecord()
    velocity = (0.0, 0.0)
    target, target_since = 0, 0.0
    in_contact = False
    backup = 0
    nav = None
    steps = int(round(o.seconds * frame_rate))
    budget = o.waypoint_timeout_s + 3 * math.dist(tour[0], true_pose[:2]) / o.speed_m_s
    for k in range(steps + 1):
        if k > 0 and stop is not None and stop.requested:
            rec.stopped_by_signal = int(getattr(stop, "signum", None) or 2)
            break
        t = k * dt
        while schedule and schedule[0][0] <= t:
            current = schedule.pop(0)[1]
            solids = Solids.of_world(current)
        rec.times_s.append(t)
        rec.poses.append(true_pose)
        rec.odometry.append(odo_pose)
        rec.estimates.append(est_pose)
        rec.clearance_m.append(solids.clearance(*true_pose[:2]) - radius)
        if target >= len(tour):
            rec.commands.append((0.0, 0.0))
            break
        # --- sense and map (the robot's own information: images or laser, odometry) ----
        image = None
        if ranger is not None:
            image = render_image(current, camera, true_pose, seed=o.seed, frame=k)
        t0 = time.perf_counter()
        amap.decay(dt)
        amap.recenter(*odo_pose[:2])
        if ranger is not None:
            if cue is not None:
                scan = cue.scan(image, timestamp=t, world_from_camera=_compose(odo_pose, mount))
            else:
                scan = ranger.scan(image, timestamp=t)
            if driven is not None:
                driven.update(odo_pose, mount, t)
            if matcher is not None:
                est_pose = matcher.correct(boundary_points_robot(scan, mount), est_pose).pose
            amap.insert_visual(scan, odo_pose, mount=mount, table=ranger.table, model=o.model)
        else:
            r = solids.laser(true_pose, angles, range_max_m=o.laser_range_m)
            if matcher is not None:
                fin = np.isfinite(r)
                pts = np.stack([r[fin] * np.cos(angles[fin]), r[fin] * np.sin(angles[fin])], 1)
                est_pose = matcher.correct(pts, est_pose).pose
            amap.insert_laser(r, angles, odo_pose, range_max_m=o.laser_range_m)
        map_from_odom = _compose(est_pose, _inverse(odo_pose))
        # --- waypoints (judged by the robot from its world-frame estimate) -------------
        goal = tuple(tour[target])
        reached = math.dist(goal, est_pose[:2]) < o.goal_tolerance_m
        if reached or t - target_since > budget:
            rec.waypoints.append(
                {
                    "index": target,
                    "x": goal[0],
                    "y": goal[1],
                    "time_s": round(t, 3),
                    "reached": bool(reached),
                    "true_error_m": round(math.dist(goal, true_pose[:2]), 4),
                }
            )
            target, target_since = target + 1, t
            nav = None
            if target >= len(tour):
                rec.commands.append((0.0, 0.0))
                rec.step_s.append(time.perf_counter() - t0)
                break
            goal = tuple(tour[target])
            budget = o.waypoint_timeout_s + 3 * math.dist(goal, est_pose[:2]) / o.speed_m_s
        # --- plan, in the odometry frame (the goal carried there) ----------------------
        goal_odom = _compose(_inverse(map_from_odom), (goal[0], goal[1], 0.0))[:2]
        cost = inflate(amap.occupied(), amap.cell, o.costmap)
        known = amap.known()
        if nav is None or k % o.replan_every == 0:
            tp = time.perf_counter()
            nav = navigation_function(
                cost,
                amap.cell,
                amap.origin_m,
                goal_odom,
                o.costmap,
                known=known,
            )
            rec.plan_s.append(time.perf_counter() - tp)
        if backup > 0:
            backup -= 1
            v, w = -BACKUP_SPEED_M_S, 0.0
        else:
            v, w, _ = choose_velocity(
                odo_pose,
                velocity,
                cost,
                amap.origin_m,
                amap.cell,
                nav,
                goal_odom,
                dt,
                dwa,
                unknown=~known,
            )
        rec.step_s.append(time.perf_counter() - t0)
        rec.commands.append((v, w))
        if o.keep_frames and k % o.keep_frames == 0 and len(rec.frames) < 400:
            rec.frames.append(
                (image, amap.probabilities().astype(np.float32), odo_pose, amap.origin_m)
            )
        # --- act, and judge contact from truth ----------------------------------------
        poses, inc = stepper.step(true_pose, v, w, k)
        blocked = False
        for p in poses[1:]:
            if solids.clearance(p[0], p[1]) < radius:
                blocked = True
                break
        if blocked:
            # the robot's bumper ring tells which of its segments touched; the robot marks
            # a face there in its map and, unless the touch was behind, backs off out of the
            # mark's inscribed radius, where its planner works again
            bearing = bumper_segment(p, solids.nearest(p[0], p[1]))
            amap.mark_bump(odo_pose, bearing, radius + 0.02)
            # the five segments not behind: backing off a side face helps too (without it
            # the robot scraped along a desk's side, 2 -> 6 contacts on the open plan)
            ahead = abs(bearing) <= math.pi / 2 + 1e-9
            backup = int(round(o.bump_backup_m / (BACKUP_SPEED_M_S * dt))) if ahead else 0
            if not in_contact:
                rec.contacts.append(
                    {"time_s": round(t, 3), "x": float(true_pose[0]), "y": float(true_pose[1])}
                )
            in_contact = True
            velocity = (0.0, 0.0)  # a bumper stop: the robot does not enter the solid
            continue
        in_contact = False
        true_pose = tuple(float(c) for c in poses[-1])
        odo_pose = _compose(odo_pose, inc)
        est_pose = _compose(map_from_odom, odo_pose)  # the prediction the next match starts at
        velocity = (v, w)
    for i in range(target, len(tour)):
        rec.waypoints.append(
            {
                "index": i,
                "x": float(tour[i][0]),
                "y": float(tour[i][1]),
                "time_s": None,
                "reached": False,
                "true_error_m": None,
            }
        )
    return DriveResult(
        world=world, final_world=current, options=o, record=rec, map=amap, camera=camera
    )
