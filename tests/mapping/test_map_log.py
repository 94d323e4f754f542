"""``floorscan map-log`` on a synthetic CARMEN log of a rectangular room (ranges cast
analytically against its walls): the map must show the walls and the free interior."""

import gzip
import math

import numpy as np
import pytest
from floorscan import DatasetError, OccupancyGrid
from floorscan.cli import main

ROOM = (-1.025, -2.025, 5.025, 2.025)  # x_min, y_min, x_max, y_max [m]: walls mid-cell at 5 cm


def cast(x, y, angle):
    """Distance from (x, y) inside the room to its walls along `angle`."""
    c, s = math.cos(angle), math.sin(angle)
    x0, y0, x1, y1 = ROOM
    ts = []
    if c > 1e-12:
        ts.append((x1 - x) / c)
    if c < -1e-12:
        ts.append((x0 - x) / c)
    if s > 1e-12:
        ts.append((y1 - y) / s)
    if s < -1e-12:
        ts.append((y0 - y) / s)
    return min(ts)


def write_room_log(path, *, beams=180, bad_line=False):
    lines = ["# synthetic room", "PARAM robot_frontlaser_offset 0.0 nohost 0"]
    for k in range(40):
        x, y, theta = 0.1 * k, 0.3 * math.sin(0.2 * k), 0.15 * k
        ranges = [cast(x, y, theta - math.pi / 2 + i * math.pi / beams) for i in range(beams)]
        ranges[5] = 81.91  # a no-return reading
        fields = " ".join(f"{r:.4f}" for r in ranges)
        lines.append(
            f"FLASER {beams} {fields} {x} {y} {theta} {x} {y} {theta} {k * 0.1} sim {k * 0.1}"
        )
        lines.append(f"ODOM {x} {y} {theta} 0 0 0 {k * 0.1} sim {k * 0.1}")
    if bad_line:
        lines.insert(7, "FLASER 3 1.0 2.0")
    with gzip.open(path, "wt") as f:
        f.write("\n".join(lines) + "\n")


@pytest.mark.parametrize("walk", [[], ["--ray-walk", "thin"]], ids=["exact", "thin"])
def test_map_log_draws_the_room(tmp_path, capsys, walk):
    log = tmp_path / "room.log.gz"
    write_room_log(log)
    out = tmp_path / "out" / "room.yaml"
    assert (
        main(
            [
                "map-log",
                str(log),
                "-o",
                str(out),
                "--png",
                str(tmp_path / "room.png"),
                "--cell-size",
                "0.05",
                *walk,
            ]
        )
        == 0
    )
    assert "mapped 40 scans" in capsys.readouterr().err
    assert (tmp_path / "room.png").is_file() and (tmp_path / "out" / "room.pgm").is_file()
    g = OccupancyGrid.load(out)
    x0, y0, x1, y1 = ROOM
    # The walls run through the middle of cells: those cells are occupied (all but a few
    # near the corners, where grazing beams to the other wall clip them).
    xs, ys = np.arange(x0 + 0.3, x1 - 0.3, 0.05), np.arange(y0 + 0.3, y1 - 0.3, 0.05)
    on_walls = (
        [(x, y1) for x in xs]
        + [(x, y0) for x in xs]
        + [(x1, y) for y in ys]
        + [(x0, y) for y in ys]
    )
    occupied = np.mean([g.is_occupied(x, y) for x, y in on_walls])
    assert occupied > 0.95, occupied
    # The interior is free, the outside unknown.
    for x in np.arange(x0 + 0.3, x1 - 0.3, 0.2):
        for y in np.arange(y0 + 0.3, y1 - 0.3, 0.2):
            assert g.is_free(x, y), (x, y)
    assert not g.is_free(x1 + 0.5, 0.0) and not g.is_occupied(x1 + 0.5, 0.0)
    # The map is the room: nothing beyond a cell outside the walls.
    (bx0, by0), (bx1, by1) = g.extent.bounds_m
    assert bx0 >= x0 - 0.03 and by0 >= y0 - 0.03 and bx1 <= x1 + 0.03 and by1 <= y1 + 0.03


def test_map_log_reports_bad_lines(tmp_path, capsys):
    log = tmp_path / "bad.log.gz"
    write_room_log(log, bad_line=True)
    assert main(["map-log", str(log), "-o", str(tmp_path / "m.yaml")]) == 1
    assert f"{log}:8: FLASER: expected 14 fields" in capsys.readouterr().err
    assert main(["map-log", str(log), "-o", str(tmp_path / "m.yaml"), "--lenient"]) == 0
    assert "skipped bad line 8" in capsys.readouterr().err


def test_map_log_refuses_an_unknown_ray_walk(tmp_path, capsys):
    log = tmp_path / "room.log.gz"
    write_room_log(log)
    args = ["map-log", str(log), "-o", str(tmp_path / "m.yaml"), "--ray-walk", "bresenham"]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert "ray_walk" in err and "exact" in err and "thin" in err
    assert not (tmp_path / "m.yaml").exists()


def test_map_log_without_lasers(tmp_path):
    (tmp_path / "empty.log").write_text("ODOM 0 0 0 0 0 0 1 h 1\n")
    with pytest.raises(DatasetError, match="no FLASER"):
        import argparse

        from floorscan.commands.map_log import run

        run(
            argparse.Namespace(
                log=str(tmp_path / "empty.log"),
                lenient=False,
                output=str(tmp_path / "m.yaml"),
                force=False,
            )
        )
