"""Runs ranging and mapping over an :class:`EvalCase` and scores everything against its truth;
runs a suite of simulated scenarios."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Sequence

import numpy as np

from ..errors import FloorscanError
from ..mapping.grid import OccupancyGrid
from ..pipeline.config import Config
from ..pipeline.mapper import Mapper, grid_kwargs, local_map_kwargs
from ..sim import simulate_run
from .calibration_error import calibrated_table
from .case import EvalCase, case_from_run
from .map_metrics import frames_to_reliable, free_known_share
from .scenarios import Scenario
from .scoring import INVALID, ColumnScores, score_columns, score_map, summarise_columns


@dataclass
class CaseResult:
    """Scores of one case: ``metrics`` (JSON-ready) and what the report draws (the worst
    frames' scans)."""

    name: str
    metrics: Dict[str, Any]
    worst: List[Dict[str, Any]] = field(default_factory=list)
    column_scores: List[ColumnScores] = field(default_factory=list)


RANGER_RIGHT_SHARE = 0.05
"""A view's ranger is right when at most this share of its first frame's columns is wrong."""


def _ranger_wrong_share(scores: ColumnScores) -> float:
    """Share of a frame's readings that are wrong, over the columns not ``invalid``."""
    read = scores.scan_status != INVALID
    return float(scores.wrong[read].mean()) if read.any() else 1.0


def median_frames(values: Sequence[Optional[int]]) -> Optional[float]:
    """Median over views, a view never reliable counting as infinitely many frames (inf when
    half or more are); None without views."""
    v = [np.inf if x is None else x for x in values]
    return float(np.median(v)) if v else None


def _final_error(poses: np.ndarray, truth: np.ndarray) -> Optional[float]:
    """Distance [m] between the last finite pose of ``poses`` (N, 3) and the truth then."""
    ok = np.all(np.isfinite(poses), axis=1) & np.all(np.isfinite(truth), axis=1)
    if not ok.any():
        return None
    k = int(np.nonzero(ok)[0][-1])
    return float(np.hypot(*(np.asarray(poses[k][:2]) - np.asarray(truth[k][:2]))))


def evaluate_case(
    case: EvalCase,
    cfg: Config,
    *,
    worst_frames: int = 2,
    reliable_starts: int = 6,
    reliable_max_frames: int = 10,
) -> CaseResult:
    """Ranges every frame with ``cfg`` and scores: boundary columns (if the case has column
    truth), the global map built with the odometry poses and with the true poses (if it has a
    true raster), free space along the path, frames to a reliable local map, speed."""
    kw = grid_kwargs(cfg)
    poses = case.odometry if case.odometry is not None else case.true_poses
    if case.odometry is None:  # true poses: nothing for scan matching to correct
        cfg = cfg.with_overrides({"slam.mode": "off"})
    mapper = Mapper(case.table, cfg, robot_from_camera=case.robot_from_camera)
    placed: List[Optional[tuple]] = []
    true_map = None
    if case.true_poses is not None and case.odometry is not None:
        true_map = OccupancyGrid(**kw)
    scans = []
    column_scores: List[ColumnScores] = []
    for k in range(len(case)):
        pose = None
        if poses is not None and np.all(np.isfinite(poses[k])):
            pose = tuple(float(v) for v in poses[k])
        scan = mapper.process(case.images[k], timestamp=float(case.timestamps[k]), pose=pose)
        placed.append(mapper.last_pose)
        scans.append(scan)
        if true_map is not None and np.all(np.isfinite(case.true_poses[k])):
            true_map.insert_scan(scan, pose=tuple(case.true_poses[k]), mount=case.robot_from_camera)
        if case.true_status is not None:
            column_scores.append(score_columns(scan, case.true_status[k], case.true_points[k]))
    if true_map is None:
        true_map = mapper.global_map if case.odometry is None else None

    n = max(mapper.frames, 1)
    metrics: Dict[str, Any] = {
        "frames": len(case),
        "ranging_ms_per_frame": 1e3 * mapper.times.ranging_s / n,
        "mapping_ms_per_frame": 1e3 * mapper.times.mapping_s / n,
        "calibration": case.calibration or {"status": "not measured"},
    }
    if mapper.slam is not None and case.odometry is not None and case.true_poses is not None:
        metrics["slam"] = {
            **mapper.slam.counts.as_dict(),
            "final_pose_error_m": {
                "odometry": _final_error(case.odometry, case.true_poses),
                "corrected": _final_error(
                    np.array([p if p is not None else (np.nan,) * 3 for p in placed]),
                    case.true_poses,
                ),
            },
        }
    worst: List[Dict[str, Any]] = []
    if column_scores:
        metrics["boundary"] = summarise_columns(column_scores).as_dict()
        rates = np.array([s.wrong.mean() for s in column_scores])
        for k in np.argsort(-rates, kind="stable")[:worst_frames]:
            worst.append({"frame": int(k), "error_rate": float(rates[k]), "scan": scans[k]})
    if case.raster is not None:
        r = case.raster
        maps = {"odometry": mapper.global_map} if case.odometry is not None else {}
        if true_map is not None:
            maps["true_poses"] = true_map
        metrics["map"] = {
            name: score_map(
                g.occupancy_classes(),
                g.extent.origin_m,
                g.extent.cell_size_m,
                r.cells,
                r.origin,
                r.resolution_m,
            ).as_dict()
            for name, g in maps.items()
        }
        if true_map is not None and case.true_poses is not None:
            metrics["free_known_share"] = free_known_share(true_map, r, case.true_poses[:, :2])
            if case.true_status is not None:
                last = len(case) - reliable_max_frames
                starts = sorted(
                    set(np.linspace(0, last, reliable_starts).astype(int).tolist())
                    if last > 0
                    else {0}
                )
                reliable = {}
                for key, kind in (
                    ("reliable_local_map", "octomap"),
                    ("reliable_avoidance_map", "avoidance"),
                ):
                    frames = frames_to_reliable(
                        scans,
                        case,
                        # run's local map: [grid], [sensors] and its own [local_map.visual]
                        {k: v for k, v in local_map_kwargs(cfg).items() if k != "size_m"},
                        local_size_m=cfg.local_map.size_m,
                        max_range_m=ranged_m(cfg),
                        starts=starts,
                        max_frames=reliable_max_frames,
                        local_map=kind,
                    )
                    reliable[key] = {
                        "frames_per_view": frames,
                        "median_frames": median_frames(frames),
                        "views_never_reliable": sum(1 for f in frames if f is None),
                        "max_frames_tried": reliable_max_frames,
                    }
                # the views where the ranger is right (issue 15's condition): at most
                # RANGER_RIGHT_SHARE of the first frame's readings wrong (columns the table
                # gives no ground are the calibration's, not the ranger's)
                right = [
                    bool(_ranger_wrong_share(column_scores[k]) <= RANGER_RIGHT_SHARE)
                    for k in starts
                ]
                for entry in reliable.values():
                    sub = [f for f, r in zip(entry["frames_per_view"], right) if r]
                    entry["frames_ranger_right"] = sub
                    entry["ranger_right_views"] = len(sub)
                    entry["median_frames_ranger_right"] = median_frames(sub)
                metrics.update(reliable)
    return CaseResult(case.name, metrics, worst, column_scores)


def simulate_scenario(scenario: Scenario, cfg: Config, *, threads: int = 2):
    """(run, case) for a scenario: simulation, then the table ranging uses (calibrated when
    calibration is available)."""
    world = scenario.build_world()
    camera = scenario.build_camera()
    run = simulate_run(
        world,
        camera=camera,
        robot=scenario.build_robot(),
        seconds=scenario.seconds,
        seed=scenario.seed,
        threads=threads,
    )
    try:
        table, cal = calibrated_table(camera, calibration=cfg.calibration.kwargs())
    except FloorscanError as e:
        table = camera.ground_table(spacing_px=cfg.calibration.spacing_px)
        cal = {"status": f"failed ({e}); ranged with the exact table"}
    case = case_from_run(scenario.name, run, table, cell_size_m=cfg.grid.cell_size_m)
    case.calibration = cal
    case.info = scenario.as_dict()
    return run, case


def run_suite(
    scenarios: Sequence[Scenario],
    cfg: Config,
    *,
    threads: int = 2,
    on_result: Optional[Callable[[int, CaseResult], None]] = None,
) -> List[Dict[str, Any]]:
    """Evaluates every scenario; returns one record per scenario: ``scenario``, ``metrics``,
    ``wall_s``, and ``result`` (the :class:`CaseResult`, with the images of its worst frames
    under ``worst[i]["image"]`` and their true rows under ``truth_rows``)."""
    records = []
    for i, sc in enumerate(scenarios):
        t0 = time.perf_counter()
        run, case = simulate_scenario(sc, cfg, threads=threads)
        t1 = time.perf_counter()
        result = evaluate_case(case, cfg)
        for w in result.worst:
            w["image"] = run.images[w["frame"]]
            w["truth_rows"] = run.truth.rows[w["frame"]]
        rec = {
            "scenario": sc.as_dict(),
            "metrics": result.metrics,
            "wall_s": {"simulate": t1 - t0, "evaluate": time.perf_counter() - t1},
            "result": result,
        }
        records.append(rec)
        if on_result is not None:
            on_result(i, result)
    return records


def ranged_m(cfg) -> float:
    """The farthest range the ranger scans [m]: ``ranger.max_range_m``, or without a limit
    (``inf``) the calibration's ground limit."""
    r = cfg.ranger.max_range_m
    return r if math.isfinite(r) else cfg.calibration.max_range_m
