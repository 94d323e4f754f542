"""Closed-loop step time (ranging + avoidance map + costmap + dynamic window; the plan's
navigation function separately, it runs every fifth frame) per frame, at a resolution.

    .venv/bin/python bench/drive_step.py --width 640 --height 480 --seconds 10
"""

from __future__ import annotations

import argparse
import json

from floorscan.drive import DriveOptions, drive
from floorscan.sim import Camera, World


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--sensor", default="camera")
    a = ap.parse_args()
    cam = Camera(width=a.width, height=a.height)
    r = drive(
        World.builtin("corridor"),
        DriveOptions(
            seconds=a.seconds, table="exact", sensor=a.sensor, keep_frames=0, columns=a.width // 2
        ),
        camera=cam,
    )
    s = r.summary()
    print(
        json.dumps(
            {
                "resolution": f"{a.width}x{a.height}",
                "frames": len(r.record.step_s),
                "step_ms_median": s["step_ms_median"],
                "plan_ms_median": s["plan_ms_median"],
            }
        )
    )


if __name__ == "__main__":
    main()
