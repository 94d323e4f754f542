"""What a drive produced: its summary (``summary.json``) and its pictures: the avoidance map
(map_server), the path drawn on the true map (PNG) and a GIF of camera + local map."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict

import numpy as np

from .._atomic import write_atomic, write_atomic_with
from ..formats.image_io import write_png
from ..sim import OccupancyRaster


@dataclass
class DriveResult:
    world: Any
    final_world: Any
    options: Any
    record: Any
    map: Any
    camera: Any

    def summary(self) -> Dict[str, Any]:
        """The figures of the run (units in the names)."""
        r = self.record
        poses = np.asarray(r.poses, np.float64)
        steps = np.hypot(*np.diff(poses[:, :2], axis=0).T) if len(poses) > 1 else np.zeros(0)
        dist = float(steps.sum())
        duration = float(r.times_s[-1]) if r.times_s else 0.0
        reached = sum(1 for w in r.waypoints if w["reached"])
        # the truth's judgement: reached by the robot, and truly within twice its tolerance
        true_tol = 2.0 * self.options.goal_tolerance_m
        truly = sum(
            1 for w in r.waypoints if w["reached"] and (w["true_error_m"] or 0.0) <= true_tol
        )
        step_ms = 1e3 * np.asarray(r.step_s) if r.step_s else np.zeros(1)
        est = np.asarray(r.estimates, np.float64).reshape(-1, 3)
        est_err = np.hypot(*(est[:, :2] - poses[:, :2]).T) if len(est) else np.zeros(1)
        return {
            "world": self.world.name,
            "sensor": self.options.sensor,
            "table": self.options.table if self.options.sensor == "camera" else None,
            "speed_m_s": self.options.speed_m_s,
            "seed": self.options.seed,
            "collisions": len(r.contacts),
            "collisions_per_100m": round(100.0 * len(r.contacts) / dist, 3) if dist > 0 else 0.0,
            "distance_m": round(dist, 3),
            "duration_s": round(duration, 3),
            "waypoints_reached": reached,
            "waypoints_total": len(r.waypoints),
            "waypoints_reached_true": truly,
            "true_tolerance_m": true_tol,
            "tour_done": bool(r.waypoints) and r.waypoints[-1]["time_s"] is not None,
            "stopped_by_signal": getattr(r, "stopped_by_signal", None),
            "min_clearance_m": round(float(min(r.clearance_m)), 4) if r.clearance_m else None,
            "mean_speed_m_s": round(dist / duration, 4) if duration > 0 else 0.0,
            "contacts": r.contacts,
            "waypoints": r.waypoints,
            "step_ms_median": round(float(np.median(step_ms)), 3),
            "plan_ms_median": round(1e3 * float(np.median(r.plan_s)), 3) if r.plan_s else None,
            "robot_radius_m": self.options.costmap.robot_radius_m,
            "scan_matching": self.options.scan_matching,
            "pose_error_m_max": round(float(est_err.max()), 4),
            "pose_error_m_final": round(float(est_err[-1]), 4),
        }

    def write(self, out, *, gif: bool = True) -> Path:
        """Writes ``summary.json``, ``map.yaml``/``map.pgm`` (the avoidance map at the end,
        map_server, odometry frame), ``path.png`` (true path on the true map, red where in
        contact, blue waypoints) and ``drive.gif``."""
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        write_atomic(out / "summary.json", json.dumps(self.summary(), indent=2) + "\n")
        self._write_map(out / "map.yaml")
        self._write_path(out / "path.png")
        if gif and self.record.frames:
            self._write_gif(out / "drive.gif")
        return out

    def _write_map(self, path: Path) -> None:
        c = self.map.occupancy_classes()
        cells = np.full(c.shape, -1, np.int8)
        cells[c == 0] = 0
        cells[c == 2] = 100
        OccupancyRaster(
            cells=cells, origin=self.map.origin_m, resolution_m=self.map.cell
        ).write_map_server(path)

    def _write_path(self, path: Path) -> None:
        res = 0.02
        raster = self.final_world.occupancy(resolution_m=res)
        img = np.stack([raster.to_pgm_image()] * 3, axis=-1).copy()
        h = img.shape[0]

        def px(x, y):
            return (int((x - raster.origin[0]) / res), h - 1 - int((y - raster.origin[1]) / res))

        import cv2

        poses = np.asarray(self.record.poses)
        pts = np.array([px(x, y) for x, y, _ in poses], np.int32)
        if len(pts) > 1:
            cv2.polylines(img, [pts], False, (0, 160, 0), 2)
        for w in self.record.waypoints:
            cv2.circle(
                img, px(w["x"], w["y"]), 5, (0, 0, 255) if w["reached"] else (255, 140, 0), 2
            )
        for c in self.record.contacts:
            cv2.circle(img, px(c["x"], c["y"]), 8, (255, 0, 0), 2)
        write_png(path, img)

    def _write_gif(self, path: Path) -> None:
        from PIL import Image

        frames = []
        for image, prob, pose, origin in self.record.frames:
            m = (255 * (1.0 - prob[::-1])).astype(np.uint8)
            m = np.stack([m] * 3, -1)
            n = m.shape[0]
            cell = self.map.cell
            i = int((pose[0] - origin[0]) / cell)
            j = n - 1 - int((pose[1] - origin[1]) / cell)
            if 0 <= i < n and 0 <= j < n:
                m[max(j - 2, 0) : j + 3, max(i - 2, 0) : i + 3] = (255, 0, 0)
                hx = int(i + 6 * math.cos(pose[2]))
                hy = int(j - 6 * math.sin(pose[2]))
                if 0 <= hx < n and 0 <= hy < n:
                    m[hy, hx] = (255, 0, 0)
            panel = Image.fromarray(m).resize((240, 240), Image.NEAREST)
            if image is not None:
                cam = Image.fromarray(image).convert("RGB").resize((320, 240))
                both = Image.new("RGB", (560, 240))
                both.paste(cam, (0, 0))
                both.paste(panel, (320, 0))
                frames.append(both)
            else:
                frames.append(panel)
        write_atomic_with(
            path,
            lambda f: frames[0].save(
                f, format="GIF", save_all=True, append_images=frames[1:], duration=500, loop=0
            ),
            suffix=".gif",
        )
