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
from ..options import check, defaults
from ..pipeline.config import Config
from ..pipeline.driven_floor import driven_floor_for
from ..pipeline.mapper import RANGER_KINDS, parallax_for, ranger_from_config
from ..sim import Camera, Robot, render_calibration, render_image
from .avoidance_map import AvoidanceMap, AvoidanceMapOptions
from .costmap import CostmapOptions, inflate, navigation_function
from .dwa import DwaOptions, choose_velocity
from .result import DriveResult
from .sensor_model import VisualSensorModel
from .solids import Solids

if TYPE_CHECKING:
    from .result import DriveResult

SENSORS = ("camera", "laser")
TABLES = ("calibrated", "exact")


@dataclass(frozen=True)
class DriveOptions:
    """Options of :func:`drive` (components have their own documented options).

    - ``speed_m_s``: top speed [m/s], in (0, 3]. Default 0.3 (the paper's top speed).
    - ``seconds``: longest run [s], > 0. Default 600; the run ends earlier when the tour is
      done once.
    - ``seed``: odometry noise and image noise. Default 0.
    - ``sensor``: ``"camera"`` (the product) or ``"laser"`` (an ideal 2-D laser, the anchor).
    - ``table``: ``"calibrated"`` (from the simulated pattern of dark lines, as ``floorscan
      demo``; the default) or ``"exact"`` (the camera's perfect table).
    - ``columns``: ranger columns, default 160 (every second column of a 320-wide image: a
      2.5 cm chair leg at 1 m spans at least one).
    - ``ranger``: the range sensor's kind, ``"edge"``, ``"appearance"`` or ``"fused"`` (a
      ``config`` given to :func:`drive` supplies the rangers' options, this their kind).
      Default ``"edge"``, the configuration's default too: on the carpet worlds the closed
      loop drives better with the paper's ranger (built-in suite at 0.8 m/s: 0 contacts
      against 2; the held-out open plan at 0.3 m/s: 93 % of waypoints against 71 %, the pose
      estimate within 0.48 m against 1.36 m: the appearance boundaries scatter more for the
      scan matcher), and its step takes ~2 ms a 640 x 480 frame against ~6 (EVALUATION.md,
      BENCHMARKS.md). Textured floors need ``"fused"``.
    - ``mid_contrast``, ``mid_range_m``: the edge ranger's lower contrast floor and the band
      of ground range [m] where it applies (``RangerOptions``' fields of the same names),
      set for the drive unless the configuration sets a band of its own; ``mid_range_m``
      None leaves the ranger's options as they are. Defaults: the ranger's ``mid_contrast``
      (0.06) over (0.6, 1.2) m, the range where an obstacle is about to be met (the dynamic
      window looks 0.5 m ahead at 0.3 m/s) but the floor's texture is averaged out: a face
      whose base is a 12-24 % step on the carpet (a wooden desk) is seen there, where the
      default floor asks for 24 % (three held-out worlds, 16 camera runs at 0.3-0.8 m/s: 5
      contacts -> 3, 0.5 m/s 3 -> 0; a 0.06 floor at every range also avoids the desk but
      reads the resolved grain near the robot as obstacles and takes 1.4-2.5x the time:
      EVALUATION.md, "A face the colour of the floor").
    - ``goal_tolerance_m``: a waypoint counts as reached (by the robot, from its pose
      estimate in the world frame) within this distance [m]. Default 0.15.
    - ``waypoint_timeout_s``: the robot gives a waypoint up after 20 s plus three times its
      straight-line travel time. Default 20.
    - ``laser_fov_rad``, ``laser_range_m``, ``laser_beams``: the ideal laser; defaults
      270 degrees, 4 m, 271 beams (a Hokuyo UTM-30LX-like scanner cut to the camera's range).
    - ``replan_every``: frames between navigation-function updates. Default 5.
    - ``keep_frames``: keep camera images and map views for a GIF every this many frames
      (0: none). Default 5.
    - ``dwa``: the dynamic window's options; its ``max_speed_m_s`` is ``speed_m_s``.
    - ``bump_backup_m``: after a bump ahead or beside (not behind), the robot reverses this
      far [m] at 0.1 m/s, in [0, 1]. Default 0.12: out of the inscribed radius (robot
      radius + footprint padding) of the face it marked, where the dynamic window works
      again (with 5 cm it stayed inside, escaped along the face and bumped it again:
      `bench/drive_bumper.py`).
    - ``scan_matching``: estimate the robot's pose in the world frame by matching each scan
      against its own persistent map (:class:`~floorscan.mapping.scan_matcher.ScanMatcher`):
      the correction ``map_from_odom`` carries the waypoints into the odometry frame the
      avoidance map and the planner work in. Default True; False drives on odometry alone.
    """

    speed_m_s: float = 0.3
    seconds: float = 600.0
    seed: int = 0
    sensor: str = "camera"
    table: str = "calibrated"
    columns: int = 160
    ranger: str = "edge"
    mid_contrast: float = field(default_factory=lambda: defaults("ranger")["mid_contrast"])
    mid_range_m: Optional[Tuple[float, float]] = (0.6, 1.2)
    goal_tolerance_m: float = 0.15
    waypoint_timeout_s: float = 20.0
    laser_fov_rad: float = 3 * math.pi / 2
    laser_range_m: float = 4.0
    laser_beams: int = 271
    replan_every: int = 5
    keep_frames: int = 5
    bump_backup_m: float = 0.12
    scan_matching: bool = True
    matcher: ScanMatcherOptions = field(default_factory=ScanMatcherOptions)
    dwa: DwaOptions = field(default_factory=DwaOptions)
    map: AvoidanceMapOptions = field(default_factory=AvoidanceMapOptions)
    costmap: CostmapOptions = field(default_factory=CostmapOptions)
    model: VisualSensorModel = field(default_factory=VisualSensorModel)

    def __post_init__(self) -> None:
        if not (0 < self.speed_m_s <= 3):
            raise OptionError(
                f"invalid option `speed`: must be in (0, 3] m/s, got {self.speed_m_s}"
            )
        if not (0 < self.seconds <= 1e5):
            raise OptionError(f"invalid option `seconds`: must be in (0, 1e5], got {self.seconds}")
        # the band is the ranger's: its rules are RangerOptions' (validated in Rust)
        band = {"mid_contrast": self.mid_contrast}
        if self.mid_range_m is not None:
            band["mid_range_m"] = list(self.mid_range_m)
        check("ranger", band)
        if not 0.0 <= self.bump_backup_m <= 1.0:
            raise OptionError(
                f"invalid option `bump_backup_m`: must be in [0, 1], got {self.bump_backup_m}"
            )
        if self.sensor not in SENSORS:
            raise OptionError(
                f"invalid option `sensor`: expected one of {SENSORS}, got {self.sensor!r}"
            )
        if self.table not in TABLES:
            raise OptionError(
                f"invalid option `table`: expected one of {TABLES}, got {self.table!r}"
            )
        if self.ranger not in RANGER_KINDS:
            raise OptionError(
                f"invalid option `ranger`: expected one of {RANGER_KINDS}, got {self.ranger!r}"
            )
        if not 2 <= int(self.columns) <= 4096:
            raise OptionError(f"invalid option `columns`: must be in 2..=4096, got {self.columns}")
        if not 1 <= int(self.laser_beams) <= 10000:
            raise OptionError(
                f"invalid option `laser_beams`: must be in 1..=10000, got {self.laser_beams}"
            )


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
