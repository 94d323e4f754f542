"""``floorscan demo``: the main job on the built-in simulated office, with no files needed.

Simulates the ``corridor`` world (the robot drives the corridor and through doorways at
0.3 m/s, 10 frames/s, with odometry drift), calibrates from the simulated calibration pattern,
runs the whole pipeline as ``floorscan run`` does, and adds what ground truth allows: the map
built with true poses beside the odometry map and the true map, the share of boundary points
more than 10 cm from the true obstacle, the maps' agreement with the true occupancy, and a
performance table in the paper's form measured on this machine.
"""

from __future__ import annotations

import json
import platform
import time
from pathlib import Path
from typing import Dict

import numpy as np

from .._atomic import write_atomic
from ..calibration import calibrate, draw_calibration_overlay
from ..formats.image_io import read_grey, write_png
from ..mapping.grid import OccupancyGrid
from ..mapping.grid_views import GridExtent
from ..pipeline.config import Config
from ..pipeline.mapper import Mapper, grid_kwargs, run
from ..pipeline.outputs import RunOutputs
from ..pipeline.sources import DatasetSource
from ..sim import World, simulate_run
from .scoring import score_columns, score_map, summarise_columns

PAPER = {
    "input_fps": 10.0,
    "output_points_per_s": 320.0,
    "ms_per_frame": 50.0,
    "map_size": "384 x 384 cm",
    "resolution_cm": 4.0,
    "ms_per_point": "< 0.02",
}


def SIMULATION_CONFIG() -> Config:
    """The configuration for simulated runs: the defaults (the table reaches as far as the
    calibration's predicted error allows, docs/calibration.md)."""
    return Config()


def calibrate_from_dataset(dataset: Path, cfg: Config, out: Path):
    """The table from the dataset's calibration scene, with its overlay and report."""
    image = read_grey(dataset / "calibration" / "pattern.png")
    table, report = calibrate(
        image,
        dataset / "calibration" / "pattern.toml",
        **cfg.calibration.kwargs(),
    )
    out.mkdir(parents=True, exist_ok=True)
    table.save(out / "table.json")
    write_png(out / "overlay.png", draw_calibration_overlay(image, table, report))
    return table, report


def common_extent(raster, cell_size_m: float) -> GridExtent:
    """The true raster's window as a grid extent (maps anchored at the world origin)."""
    x_cell = int(round(raster.origin[0] / cell_size_m))
    y_cell = int(round(raster.origin[1] / cell_size_m))
    h, w = raster.cells.shape
    scale = raster.resolution_m / cell_size_m
    return GridExtent(
        x_cell,
        y_cell,
        int(round(w * scale)),
        int(round(h * scale)),
        cell_size_m,
        (x_cell * cell_size_m, y_cell * cell_size_m),
    )


def side_by_side(panels, titles, path: Path) -> Path:
    from PIL import Image, ImageDraw

    h = max(p.shape[0] for p in panels)
    gap, head = 8, 18
    w = sum(p.shape[1] for p in panels) + gap * (len(panels) - 1)
    canvas = Image.new("L", (w, h + head), 255)
    draw = ImageDraw.Draw(canvas)
    x = 0
    for p, t in zip(panels, titles):
        canvas.paste(Image.fromarray(p), (x, head))
        draw.text((x + 4, 3), t, fill=0)
        x += p.shape[1] + gap
    arr = np.asarray(canvas)
    return write_png(path, arr)


def run_demo(
    out: Path, *, world_name: str = "corridor", seconds: float = 60.0, seed: int = 0
) -> Dict[str, object]:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cfg = SIMULATION_CONFIG()
    t_start = time.perf_counter()
    world = World.builtin(world_name)
    sim = simulate_run(world, seconds=seconds, seed=seed, threads=2)
    # The paper's calibration pattern: taped lines at 20 cm, reaching about 2 m (a small
    # checkerboard near the robot calibrates only the first metre or so: docs/calibration.md).
    dataset = sim.write_dataset(out / "dataset", overwrite=True, calibration="lines")
    t_sim = time.perf_counter()

    table, report = calibrate_from_dataset(dataset, cfg, out / "calibration")
    t_cal = time.perf_counter()

    # 1. The product's main job, exactly as `floorscan run DATASET` does it: odometry poses.
    source = DatasetSource(dataset)
    mapper = Mapper(table, cfg, robot_from_camera=source.rig.robot_from_camera)
    outputs = RunOutputs(out / "run", cfg, expected_frames=len(source))
    stats = run(source, mapper, outputs)
    t_run = time.perf_counter()

    # 2. The same frames with the true poses (decoded images already in memory), scored; and
    # their scans at the odometry poses as they are (the map without scan matching).
    plain = cfg.with_overrides({"slam.mode": "off"})
    truth_mapper = Mapper(table, plain, robot_from_camera=source.rig.robot_from_camera)
    uncorrected = OccupancyGrid(**grid_kwargs(cfg))
    column_scores = []
    for k in range(len(sim)):
        scan = truth_mapper.process(
            sim.images[k], timestamp=float(sim.timestamps[k]), pose=tuple(sim.poses[k])
        )
        uncorrected.insert_scan(
            scan, pose=tuple(sim.odometry[k]), mount=source.rig.robot_from_camera
        )
        column_scores.append(score_columns(scan, sim.truth.status[k], sim.truth.points[k]))
    boundary = summarise_columns(column_scores)

    # 3. Maps against the true occupancy.
    raster = world.occupancy(resolution_m=cfg.grid.cell_size_m)
    scores = {}
    maps = (
        ("odometry", mapper.global_map),
        ("odometry_without_matching", uncorrected),
        ("true_poses", truth_mapper.global_map),
    )
    for name, grid in maps:
        ext = grid.extent
        scores[name] = score_map(
            grid.occupancy_classes(),
            ext.origin_m,
            ext.cell_size_m,
            raster.cells,
            raster.origin,
            raster.resolution_m,
        ).as_dict()
    truth_mapper.global_map.save(out / "map_true_poses.yaml")
    raster.write_map_server(out / "map_truth.yaml")
    ext = common_extent(raster, cfg.grid.cell_size_m)
    panels = [
        mapper.global_map.to_image(extent=ext),
        truth_mapper.global_map.to_image(extent=ext),
        raster.to_pgm_image(),
    ]
    # Crop to what the robot saw (plus a margin): a 60 s tour does not cover the whole world.
    known = truth_mapper.global_map.occupancy_classes(extent=ext)[::-1] != 1
    rows, cols = np.nonzero(known)
    if rows.size:
        m = 12
        r0, r1 = max(rows.min() - m, 0), min(rows.max() + m + 1, known.shape[0])
        c0, c1 = max(cols.min() - m, 0), min(cols.max() + m + 1, known.shape[1])
        panels = [p[r0:r1, c0:c1] for p in panels]
    panels = [np.repeat(np.repeat(p, 2, axis=0), 2, axis=1) for p in panels]
    side_by_side(
        panels, ["odometry poses", "true poses", "true map"], out / "maps_side_by_side.png"
    )
    t_end = time.perf_counter()

    n = max(mapper.frames, 1)
    ranging_ms = 1e3 * mapper.times.ranging_s / n
    mapping_ms = 1e3 * mapper.times.mapping_s / n
    points = mapper.points
    ours = {
        "input_fps": 1e3 / (ranging_ms + mapping_ms),
        "output_points_per_s": points / max(mapper.times.ranging_s + mapper.times.mapping_s, 1e-12),
        "ms_per_frame": ranging_ms,
        "map_size": f"{cfg.local_map.size_m * 100:.0f} x {cfg.local_map.size_m * 100:.0f} cm local; global grows",
        "resolution_cm": cfg.grid.cell_size_m * 100,
        "ms_per_point": 1e3 * mapper.times.mapping_s / max(points, 1),
        "points_per_frame": points / n,
    }
    summary = {
        "world": world_name,
        "frames": len(sim),
        "seconds_simulated": seconds,
        "machine": f"{platform.machine()}, {platform.python_implementation()} {platform.python_version()}, one core",
        "calibration": report.as_dict() if hasattr(report, "as_dict") else str(report),
        "boundary": boundary.as_dict(),
        "map_agreement": scores,
        "performance": ours,
        "paper": PAPER,
        "wall_s": {
            "simulate_and_write": t_sim - t_start,
            "calibrate": t_cal - t_sim,
            "run": t_run - t_cal,
            "true_poses_and_scoring": t_end - t_run,
            "total": t_end - t_start,
        },
        "run_counts": stats.as_dict(),
    }
    write_atomic(out / "demo_summary.json", json.dumps(summary, indent=2, default=float))
    write_atomic(out / "performance.md", performance_table(ours))
    return summary


def performance_table(ours: Dict[str, object]) -> str:
    rows = [
        ("Visual range subsystem", "", ""),
        (
            "Input rate (frames/s, achievable)",
            f"{PAPER['input_fps']:.0f}",
            f"{ours['input_fps']:.0f}",
        ),
        (
            "Output rate (points/s)",
            f"{PAPER['output_points_per_s']:.0f}",
            f"{ours['output_points_per_s']:.0f}",
        ),
        (
            "Processing time (ms/frame)",
            f"{PAPER['ms_per_frame']:.0f}",
            f"{ours['ms_per_frame']:.3f}",
        ),
        ("Map building subsystem", "", ""),
        ("Map size", PAPER["map_size"], str(ours["map_size"])),
        ("Map resolution (cm)", f"{PAPER['resolution_cm']:.0f}", f"{ours['resolution_cm']:.0f}"),
        ("Processing time (ms/point)", str(PAPER["ms_per_point"]), f"{ours['ms_per_point']:.5f}"),
    ]
    lines = ["| | paper (33 MHz 486) | floorscan (this machine) |", "|---|---:|---:|"]
    lines += [f"| {a} | {b} | {c} |" for a, b, c in rows]
    return "\n".join(lines) + "\n"
