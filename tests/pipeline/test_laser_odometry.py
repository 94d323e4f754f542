"""A laser log mapped from raw odometry (``floorscan map-log --poses odometry``): a synthetic
corrected log of a room (ranges cast analytically, the true poses written as the corrected ones,
the ODOM lines a drifting odometry anchored at each scan as a SLAM run writes them). Scan
matching must bring the path and the map back near the true ones; dead reckoning must not."""

import gzip
import math

import numpy as np
import pytest
from floorscan import OccupancyGrid
from floorscan.cli import main
from floorscan.errors import ConfigError
from floorscan.formats.carmen import read_carmen
from floorscan.formats.trajectory import compose, read_tum
from floorscan.mapping import pose_graph
from floorscan.pipeline.config import Config
from floorscan.pipeline.laser_odometry import beam_ends_robot, lasers_at_odometry

ROOM = (-1.0, -2.5, 7.0, 3.5)  # x_min, y_min, x_max, y_max [m]
PILLARS = [(2.0, 1.5, 0.3), (4.5, -1.0, 0.4)]  # centre x, y, half side [m]: square pillars


def inverse(p):
    c, s = math.cos(p[2]), math.sin(p[2])
    return (-c * p[0] - s * p[1], s * p[0] - c * p[1], -p[2])


def segments():
    x0, y0, x1, y1 = ROOM
    out = [((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))]
    for cx, cy, h in PILLARS:
        c = [(cx - h, cy - h), (cx + h, cy - h), (cx + h, cy + h), (cx - h, cy + h)]
        out += [(c[i], c[(i + 1) % 4]) for i in range(4)]
    return out


def cast(x, y, angle):
    """Distance along ``angle`` from (x, y) to the nearest wall or pillar face."""
    d = np.array([math.cos(angle), math.sin(angle)])
    best = math.inf
    for a, b in segments():
        a, b = np.array(a), np.array(b)
        e = b - a
        m = np.array([[d[0], -e[0]], [d[1], -e[1]]])
        if abs(np.linalg.det(m)) < 1e-12:
            continue
        t, u = np.linalg.solve(m, a - np.array([x, y]))
        if t > 1e-9 and -1e-9 <= u <= 1 + 1e-9:
            best = min(best, t)
    return best


def true_path(n=120, laps=1):
    """Loops around the room's middle: (x, y, yaw) per scan."""
    out = []
    for k in range(n * laps):
        a = 2 * math.pi * k / n
        out.append((3.0 + 2.2 * math.cos(a), 0.5 + 1.6 * math.sin(a), a + math.pi / 2))
    return out


def write_log(path, beams=181, laps=1, glitch=None):
    """``glitch``: (scan index, radians) one odometry step turned wrong by that much."""
    truth = true_path(laps=laps)
    # Odometry's motions: the true ones with its turns 8 % too large and its distances 3 % short.
    raw = [truth[0]]
    for k in range(1, len(truth)):
        m = compose(inverse(truth[k - 1]), truth[k])
        turn = 1.08 * m[2] + (glitch[1] if glitch and glitch[0] == k else 0.0)
        raw.append(compose(raw[-1], (0.97 * m[0], 0.97 * m[1], turn)))
    lines = ["# synthetic corrected log"]
    for k, (x, y, th) in enumerate(truth):
        step = math.pi / (beams - 1)
        ranges = [cast(x, y, th - math.pi / 2 + i * step) for i in range(beams)]
        fields = " ".join(f"{r:.4f}" for r in ranges)
        t = 0.5 * k
        lines.append(f"FLASER {beams} {fields} {x} {y} {th} {x} {y} {th} {t} sim {t}")
        lines.append(f"ODOM {x} {y} {th} 0 0 0 0 sim 0")  # the anchor
        if k + 1 < len(truth):
            moved = compose(compose((x, y, th), inverse(raw[k])), raw[k + 1])
            lines.append(f"ODOM {moved[0]} {moved[1]} {moved[2]} 0 0 0 {t + 0.5} sim {t + 0.5}")
    with gzip.open(path, "wt") as f:
        f.write("\n".join(lines) + "\n")
    return np.array(truth)


def agreement(a: OccupancyGrid, b: OccupancyGrid) -> float:
    """Share of the cells ``b`` knows that ``a`` classifies alike."""
    cb = b.occupancy_classes()
    ca = a.occupancy_classes(extent=b.extent)
    known = cb != 1
    return float((ca[known] == cb[known]).mean())


def test_beam_ends_are_in_the_robot_frame():
    log_line = "FLASER 3 1 2 1 0 0.1 1.5707963267948966 0 0 1.5707963267948966 0 h 0"
    from floorscan.formats.carmen import parse_carmen_lines

    (r,) = parse_carmen_lines([log_line]).lasers
    ends = beam_ends_robot(r, 40.0, 0.05)
    # beams at -90, 0, +90 degrees from a laser 0.1 m ahead of the robot (facing +y in the world)
    np.testing.assert_allclose(ends, [[0.1, -1.0], [2.1, 0.0], [0.1, 1.0]], atol=1e-12)


def test_scan_matching_takes_back_most_of_odometrys_drift(tmp_path):
    log_path = tmp_path / "room.log.gz"
    truth = write_log(log_path)
    log = read_carmen(log_path)
    cfg = Config().with_overrides({"slam.mode": "local"})
    off = cfg.with_overrides({"slam.mode": "off"})
    raw_lasers, raw_summary = lasers_at_odometry(log, off, range_max_m=40.0, range_min_m=0.05)
    matched, summary = lasers_at_odometry(log, cfg, range_max_m=40.0, range_min_m=0.05)
    assert raw_summary["odometry"] == summary["odometry"] == "rebuilt from the log's anchors"
    raw_err = np.array([r.laser_pose for r in raw_lasers])[:, :2] - truth[:, :2]
    err = np.array([r.laser_pose for r in matched])[:, :2] - truth[:, :2]
    raw_end, end = np.hypot(*raw_err[-1]), np.hypot(*err[-1])
    assert raw_end > 0.5, raw_end  # the drift is real
    assert end < 0.25 * raw_end and np.hypot(err[:, 0], err[:, 1]).max() < 0.3
    assert summary["frames_matched"] > 0.8 * len(truth)

    # End to end: the maps against the map at the log's (true) poses.
    maps = {}
    for name, extra in [
        ("log", []),
        ("matched", ["--poses", "odometry", "--slam", "local"]),
        ("raw", ["--poses", "odometry", "--slam", "off"]),
    ]:
        out = tmp_path / f"{name}.yaml"
        assert main(["map-log", str(log_path), "-o", str(out), *extra]) == 0
        maps[name] = OccupancyGrid.load(out)
    matched_agree, raw_agree = (
        agreement(maps["matched"], maps["log"]),
        agreement(maps["raw"], maps["log"]),
    )
    assert matched_agree > 0.9 and matched_agree > raw_agree + 0.1, (matched_agree, raw_agree)


@pytest.mark.skipif(not pose_graph.AVAILABLE, reason="GTSAM is not installed (floorscan[slam])")
def test_the_pose_graph_closes_the_loops_of_a_second_lap(tmp_path, capsys):
    log_path = tmp_path / "laps.log.gz"
    truth = write_log(log_path, laps=2)  # 24 m of travel: the second lap passes the first
    log = read_carmen(log_path)
    cfg = Config().with_overrides({"slam.mode": "graph"})
    lasers, summary = lasers_at_odometry(log, cfg, range_max_m=40.0, range_min_m=0.05)
    raw, _ = lasers_at_odometry(
        log, cfg.with_overrides({"slam.mode": "off"}), range_max_m=40.0, range_min_m=0.05
    )
    assert summary["loop_closures"] > 0 and summary["keyframes"] < len(truth)
    err = np.array([r.laser_pose for r in lasers]) - truth
    raw_err = np.array([r.laser_pose for r in raw]) - truth
    assert np.hypot(*raw_err[-1, :2]) > 1.0  # the drift is real
    d = np.hypot(err[:, 0], err[:, 1])
    assert np.percentile(d, 95) < 0.1 and d[-1] < 0.1 and d.max() < 0.5, d.max()
    yaw = np.abs(np.remainder(err[:, 2] + math.pi, 2 * math.pi) - math.pi)
    assert np.percentile(yaw, 95) < 0.03 and yaw[-1] < 0.03

    # map-log's default with --poses odometry is the graph; its map matches the log's
    out, reference = tmp_path / "graph.yaml", tmp_path / "log.yaml"
    assert main(["map-log", str(log_path), "-o", str(reference)]) == 0
    tum = tmp_path / "graph.tum"
    args = [
        "map-log",
        str(log_path),
        "-o",
        str(out),
        "--poses",
        "odometry",
        "--trajectory",
        str(tum),
    ]
    assert main(args) == 0
    assert "loop closures" in capsys.readouterr().err
    # the trajectory file holds the poses the map was built at; the odometry beside it
    placed, odometry = read_tum(tum), read_tum(tmp_path / "graph_odometry.tum")
    assert len(placed) == len(odometry) == len(truth)
    d = np.hypot(placed.x - truth[:, 0], placed.y - truth[:, 1])
    assert np.percentile(d, 95) < 0.1
    assert np.hypot(odometry.x[-1] - truth[-1, 0], odometry.y[-1] - truth[-1, 1]) > 1.0
    # (poses off by 2 cm / 0.3 degrees at random give about 96 % on a real log's map)
    assert agreement(OccupancyGrid.load(out), OccupancyGrid.load(reference)) > 0.92


def test_without_gtsam_map_log_falls_back_to_local_matching_and_says_so(
    tmp_path, capsys, monkeypatch
):
    log_path = tmp_path / "room.log.gz"
    write_log(log_path)
    monkeypatch.setattr(pose_graph, "AVAILABLE", False)
    monkeypatch.setattr(pose_graph, "gtsam", None)
    out = tmp_path / "m.yaml"
    assert main(["map-log", str(log_path), "-o", str(out), "--poses", "odometry"]) == 0
    err = capsys.readouterr().err
    assert "GTSAM is not installed" in err and "scan matching:" in err
    # asked for directly, the graph is a one-line configuration error
    with pytest.raises(ConfigError, match="floorscan\\[slam\\]"):
        lasers_at_odometry(
            read_carmen(log_path),
            Config().with_overrides({"slam.mode": "graph"}),
            range_max_m=40.0,
            range_min_m=0.05,
        )


@pytest.mark.skipif(not pose_graph.AVAILABLE, reason="GTSAM is not installed (floorscan[slam])")
def test_one_odometry_step_turned_wrong_by_50_degrees_is_caught(tmp_path):
    # (the Seattle log has one such step: 80 degrees)
    log_path = tmp_path / "glitch.log.gz"
    truth = write_log(log_path, laps=2, glitch=(60, math.radians(50.0)))
    log = read_carmen(log_path)
    cfg = Config().with_overrides({"slam.mode": "graph"})
    ends = {}
    for recovery in (0.0, 1.6):
        c = cfg.with_overrides({"slam.graph.recovery_yaw_rad": recovery})
        lasers, summary = lasers_at_odometry(log, c, range_max_m=40.0, range_min_m=0.05)
        end = np.array(lasers[-1].laser_pose) - truth[-1]
        ends[recovery] = (math.hypot(end[0], end[1]), summary["frames_recovered"])
    assert ends[1.6][1] >= 1 and ends[1.6][0] < 0.1, ends
    assert ends[0.0][1] == 0 and ends[0.0][0] > 1.0, ends
