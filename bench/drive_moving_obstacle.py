"""A moved obstacle in closed loop (issue 15 item 2: stale evidence must clear).

A 10 x 1.8 m hall (a world written here, not one the drive's settings were chosen on): the
robot drives to the far end and back. A 0.5 m box stands against the south wall at x = 5 m;
while the robot is at the far end the box is moved to the north wall at the same x (the
simulator's ``changes``: contact and the laser use the current world). On the way back the
robot must drive where the box was (its old cells must clear: the remembered box and the new
one together leave no way through) and around where it is now.

Reported per seed and sensor: contacts, waypoints reached, time; and, from the avoidance
map's recorded probabilities (every frame), how long after the move the old box's cells stop
reading occupied (calibrated probability below 0.5 at every cell of its face) and how long
until the new box's face reads occupied. A control run leaves the box where it was.

    .venv/bin/python bench/drive_moving_obstacle.py [--seeds 3] [--speed 0.3]
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np
from floorscan.drive import DriveOptions, drive
from floorscan.sim import World

HALL = """
name = "moving-box hall"
seed = 11
tour = [[9.0, 0.9], [0.9, 0.9]]
[start]
x = 0.8
y = 0.9
yaw = 0.0
[coverings.carpet]
kind = "carpet"
brightness = 0.35
contrast = 0.06
[lighting]
ambient = 0.55
grid = { spacing_m = 2.5, power = 0.6 }
[[walls]]
from = [0.0, 0.0]
to = [10.0, 0.0]
[[walls]]
from = [10.0, 0.0]
to = [10.0, 1.8]
[[walls]]
from = [10.0, 1.8]
to = [0.0, 1.8]
[[walls]]
from = [0.0, 1.8]
to = [0.0, 0.0]
"""

KEEP = 2
"""A map view every this many frames (the drive keeps at most 400: 80 s)."""
SOUTH = (5.0, 0.3)
NORTH = (5.0, 1.5)


def box(centre) -> str:
    return (
        f"\n[[boxes]]\ncenter = [{centre[0]}, {centre[1]}]\nsize = [0.5, 0.5]\n"
        'height_m = 0.6\nappearance = "metal"\n'
    )


def face_points(centre, step=0.05):
    """Points just inside the box's west and east faces and along its length (x, y) [m]."""
    ys = np.arange(centre[1] - 0.2, centre[1] + 0.21, step)
    xs = np.array([centre[0] - 0.22, centre[0] + 0.22])
    return np.array([(x, y) for x in xs for y in ys])


def to_odometry(points, true_pose, odo_pose):
    """World points into the odometry frame of a frame whose true and odometry poses are
    given: odo_from_world = odo_pose * true_pose^-1."""
    tx, ty, tth = true_pose
    ox, oy, oth = odo_pose
    c, s = math.cos(-tth), math.sin(-tth)
    dx, dy = points[:, 0] - tx, points[:, 1] - ty
    rx, ry = c * dx - s * dy, s * dx + c * dy  # robot frame
    c, s = math.cos(oth), math.sin(oth)
    return np.stack([ox + c * rx - s * ry, oy + s * rx + c * ry], 1)


def occupied_share(frame, points_odo, cell_m) -> float:
    _, prob, _, origin = frame
    i = np.floor((points_odo[:, 0] - origin[0]) / cell_m).astype(int)
    j = np.floor((points_odo[:, 1] - origin[1]) / cell_m).astype(int)
    h, w = prob.shape
    ok = (i >= 0) & (i < w) & (j >= 0) & (j < h)
    p = np.zeros(len(points_odo))
    p[ok] = prob[j[ok], i[ok]]
    return float((p >= 0.5).mean())


def run(seed: int, speed: float, sensor: str, moved: bool) -> dict:
    before = World.from_toml(HALL + box(SOUTH))
    after = World.from_toml(HALL + box(NORTH)) if moved else before
    t_move = 8.2 / speed * 1.1 + 2.0  # the robot is near the far end by then
    o = DriveOptions(
        speed_m_s=speed, seed=seed, sensor=sensor, table="exact", keep_frames=KEEP, seconds=120.0
    )
    r = drive(before, o, changes=[(t_move, after)])
    s = r.summary()
    rec = r.record
    out = {
        "seed": seed,
        "sensor": sensor,
        "moved": moved,
        "collisions": s["collisions"],
        "waypoints": f"{s['waypoints_reached']}/{s['waypoints_total']}",
        "duration_s": s["duration_s"],
    }
    if moved and rec.frames:
        cell = o.map.cell_size_m
        k_move = int(math.ceil(t_move * 10))
        old, new = face_points(SOUTH), face_points(NORTH)
        cleared = occupied_new = None
        for i, frame in enumerate(rec.frames):
            k = i * KEEP  # the step this map view was recorded at
            if k < k_move or k >= len(rec.poses):
                continue
            pts_old = to_odometry(old, rec.poses[k], rec.odometry[k])
            pts_new = to_odometry(new, rec.poses[k], rec.odometry[k])
            if cleared is None and occupied_share(frame, pts_old, cell) == 0.0:
                cleared = round((k - k_move) / 10, 1)
            if occupied_new is None and occupied_share(frame, pts_new, cell) >= 0.5:
                occupied_new = round((k - k_move) / 10, 1)
        out["old_cells_clear_after_s"] = cleared
        out["new_box_occupied_after_s"] = occupied_new
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--speed", type=float, default=0.3)
    a = ap.parse_args()
    for seed in range(a.seeds):
        for sensor in ("camera", "laser"):
            for moved in (True, False):
                print(json.dumps(run(seed, a.speed, sensor, moved)), flush=True)


if __name__ == "__main__":
    main()
