"""Hostile inputs of issue 12, each a ``floorscan`` command line run as its own process.

Used by tests/test_hostile_cli.py (every case must end with its expected exit code, at most one
line on stderr, no traceback, no temporary file, under 1 GB of memory, within the time limit)
and by bench/hostile_inputs.py (which prints the table of peak memory per case).

A case builds its files under a fresh folder and returns the command's arguments; ``shared``
holds a small dataset (``shared/room``) and its ground table (``shared/table.json``).
"""

from __future__ import annotations

import json
import math
import os
import resource
import signal
import struct
import subprocess
import sys
import time
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence

FLOORSCAN = os.environ.get("FLOORSCAN_EXE") or str(Path(sys.executable).with_name("floorscan"))
"""The command under test (FLOORSCAN_EXE runs the corpus against another build)."""
MEMORY_LIMIT_BYTES = 3 << 30
"""Address-space cap of each child (protects the machine from the old behaviour)."""
PEAK_RSS_BUDGET_MB = 1024.0
TIMEOUT_S = 120.0

EXIT_OK, EXIT_ERROR, EXIT_OS = 0, 1, 3


@dataclass
class Case:
    name: str
    build: Callable[[Path, Path], List[str]]
    exit_codes: Sequence[int] = (EXIT_ERROR,)
    stderr_has: Optional[str] = None
    check: Optional[Callable[[Path], None]] = None
    """Extra assertions on the case folder after the run."""
    needs: Sequence[str] = ()
    """Optional modules the case needs (its test skips without them)."""


@dataclass
class Result:
    name: str
    rc: Optional[int]
    stderr: str
    peak_rss_mb: float
    seconds: float
    hang: bool = False
    temp_files: List[str] = field(default_factory=list)

    @property
    def traceback(self) -> bool:
        return "Traceback" in self.stderr or "PanicException" in self.stderr

    @property
    def stderr_lines(self) -> List[str]:
        return [line for line in self.stderr.splitlines() if line.strip()]


# --- builders of hostile files -----------------------------------------------------------


def png_claiming(width: int, height: int) -> bytes:
    """A PNG whose header claims width x height 8-bit grey pixels (its data is one row): what
    a decompression bomb's header looks like to a reader."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (
            struct.pack(">I", len(data))
            + kind
            + data
            + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
        )

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    idat = zlib.compress(b"\x00" * (width + 1), 9)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def table_json(**fields) -> str:
    d = {
        "format": "floorscan.ground_table",
        "version": 1,
        "image_width": 4,
        "image_height": 4,
        "spacing_px": 4,
        "nodes_u": 2,
        "nodes_v": 2,
        "x_m": [1.0, 1.0, 2.0, 2.0],
        "y_m": [0.5, -0.5, 0.5, -0.5],
    }
    d.update(fields)
    return json.dumps(d)


def copy_dataset(shared: Path, dst: Path) -> Path:
    import shutil

    shutil.copytree(shared / "room", dst)
    return dst


def carmen_log(path: Path, far_x: Optional[float]) -> Path:
    lines = []
    for k in range(11):
        x = far_x if (far_x is not None and k == 5) else 0.1 * k
        ranges = " ".join("2.0" for _ in range(36))
        lines.append(f"FLASER 36 {ranges} {x} 0.0 0.0 {x} 0.0 0.0 {k * 0.1} sim {k * 0.1}")
    path.write_text("\n".join(lines) + "\n")
    return path


def labels_csv(d: Path) -> Path:
    """Hand labels for two frames, so that `tune` reaches its grid search."""
    p = d / "labels.csv"
    p.write_text("image,column,row\n0,40,60.5\n1,90,61.0\n")
    return p


def run_args(shared: Path, dataset: Path, out: Path, *extra: str) -> List[str]:
    return ["run", str(dataset), "--table", str(shared / "table.json"), "-o", str(out), *extra]


def config_file(d: Path, text: str) -> Path:
    p = d / "config.toml"
    p.write_text(text)
    return p


BAD_CONFIGS: Dict[str, str] = {
    "half_width_0": "[ranger]\nhalf_width = 0\n",
    "half_width_huge": "[ranger]\nhalf_width = 100000\n",
    "threshold_negative": "[ranger]\nthreshold = -1.0\n",
    "columns_0": "[ranger]\ncolumns = 0\n",
    "refine_best": '[ranger]\nrefine = "best"\n',
    "max_range_0": "[ranger]\nmax_range_m = 0.0\n",
    "auto_k_negative": "[ranger]\nauto_threshold_k = -1.0\n",
    "bottom_margin_negative": "[ranger]\nbottom_margin = -1\n",
    "spacing_0": "[calibration]\nspacing_px = 0\n",
    "coverage_bad": '[calibration]\ncoverage = "everywhere"\n',
    "max_error_fraction_0": "[calibration]\nmax_error_fraction = 0.0\n",
    "cell_0": "[map]\ncell_size_m = 0.0\n",
    "clamp_positive": "[map]\nclamp_min_nats = 1.0\n",
    "occupied_low": "[map]\noccupied_threshold = 0.3\n",
    "local_size_0": "[map]\nlocal_size_m = 0.0\n",
    "max_cells_0": "[map]\nmax_cells = 0\n",
    "hit_negative": "[sensors.visual]\nhit_nats = -1.0\n",
    "miss_positive": "[sensors.laser]\nmiss_nats = 1.0\n",
    "too_close_bad": '[sensors]\ntoo_close = "sometimes"\n',
    "margin_negative": "[sensors]\nboundary_margin_rows = -1.0\n",
    "overlay_avi": '[outputs]\noverlay = "avi"\n',
    "overlay_frames_negative": "[outputs]\noverlay_max_frames = -5\n",
    "overlay_mb_0": "[outputs]\noverlay_max_mb = 0\n",
    "snapshot_negative": "[outputs]\nlocal_snapshot_period_s = -1.0\n",
    "laser_increment_0": "[outputs]\nlaser_angle_increment_rad = 0.0\n",
    "bag_storage_bad": '[outputs]\nbag_storage = "tape"\n',
    "max_image_pixels_0": "[limits]\nmax_image_pixels = 0\n",
    "unknown_key": "[ranger]\nthreshhold = 3.0\n",
}


def _cases() -> List[Case]:
    cases: List[Case] = []
    add = cases.append

    # Rust panics / aborts across the FFI.
    def overflow_table(d, s):
        big = 1 << 33
        (d / "t.json").write_text(
            table_json(
                image_width=big,
                image_height=1 << 31,
                spacing_px=1,
                nodes_u=big,
                nodes_v=1 << 31,
                x_m=[],
                y_m=[],
            )
        )
        return ["scan", str(s / "room"), "--table", str(d / "t.json"), "-o", str(d / "s.csv")]

    add(Case("table_nodes_overflow", overflow_table, stderr_has="ground table"))

    def huge_image_table(d, s):
        (d / "t.json").write_text(
            table_json(image_width=10**9, image_height=10**9, spacing_px=10**9)
        )
        return ["scan", str(s / "room"), "--table", str(d / "t.json"), "-o", str(d / "s.csv")]

    add(Case("table_1e9_image", huge_image_table, stderr_has="larger than"))

    for x in (1e5, 1e6):
        add(
            Case(
                f"map_log_pose_at_{x:.0e}",
                lambda d, s, x=x: [
                    "map-log",
                    str(carmen_log(d / "l.log", x)),
                    "-o",
                    str(d / "m.yaml"),
                ],
                stderr_has="max_cells",
            )
        )

    def far_odometry(d, s):
        ds = copy_dataset(s, d / "ds")
        lines = (ds / "odometry.txt").read_text().splitlines()
        k = len(lines) // 2
        parts = lines[k].split()
        parts[1] = "1000000.0"  # 1000 km
        lines[k] = " ".join(parts)
        (ds / "odometry.txt").write_text("\n".join(lines) + "\n")
        return run_args(s, ds, d / "out")

    def far_checked(d):
        summary = json.loads((d / "out" / "summary.json").read_text())
        assert summary["counts"]["skipped_out_of_map"] >= 1, summary["counts"]
        assert summary["counts"]["frames_mapped"] >= 1

    add(Case("run_odometry_at_1000_km", far_odometry, (EXIT_OK,), check=far_checked))

    def overlay_12000(d, s):
        cfg = config_file(d, "[outputs]\noverlay_max_frames = 12000\noverlay_max_mb = 1\n")
        return run_args(s, s / "room", d / "out", "--config", str(cfg))

    add(Case("run_overlay_max_frames_12000", overlay_12000, (EXIT_OK,)))

    def bomb_in_bag(d, s):
        import cv2
        import numpy as np
        from floorscan.formats.dataset import read_images_txt
        from floorscan.formats.image_io import read_grey
        from floorscan.formats.rosbag import write_image_odometry_bag
        from floorscan.formats.trajectory import read_tum

        entries = read_images_txt(s / "room")
        frames = [(e.timestamp, read_grey(e.path)) for e in entries]
        frames[2] = (frames[2][0], np.zeros((1, 1), np.uint8))  # marks the bomb
        real = cv2.imencode

        def encode(ext, img, *a):
            if img.shape == (1, 1):
                return True, np.frombuffer(png_claiming(32700, 32700), np.uint8)
            return real(ext, img, *a)

        cv2.imencode = encode
        try:
            write_image_odometry_bag(
                d / "bag", frames, read_tum(s / "room" / "odometry.txt"), compressed=True
            )
        finally:
            cv2.imencode = real
        return run_args(s, d / "bag", d / "out")

    def bomb_checked(d):
        counts = json.loads((d / "out" / "summary.json").read_text())["counts"]
        assert counts["skipped_unreadable"] == 1 and counts["frames_mapped"] >= 1, counts

    add(
        Case(
            "run_bag_with_32700px_png",
            bomb_in_bag,
            (EXIT_OK,),
            check=bomb_checked,
            needs=("rosbags",),
        )
    )

    def far_wall(d, s):
        w = d / "w.toml"
        w.write_text(
            'name = "far"\nceiling_m = 2.5\n[start]\nx = 0.5\ny = 0.5\nyaw = 0.0\n'
            "[[walls]]\nfrom = [0.0, 0.0]\nto = [1e12, 0.0]\n"
        )
        return ["sim", "--world", str(w), "--seconds", "1", "--out", str(d / "sim")]

    add(Case("sim_wall_to_1e12", far_wall))

    for spec in ("0:100:1e-9", "a:b:c", "1:10:0", "1:2", "nan:1:1", ""):
        add(
            Case(
                f"tune_thresholds_{spec or 'empty'}",
                lambda d, s, spec=spec: [
                    "tune",
                    str(s / "room"),
                    "--table",
                    str(s / "table.json"),
                    "--labels",
                    str(labels_csv(d)),
                    "--thresholds",
                    spec,
                    "-o",
                    str(d / "t.toml"),
                ],
                stderr_has="--thresholds",
            )
        )

    def sim_tour_at_start(d, s):
        w = d / "w.toml"
        w.write_text(
            'name = "still"\nceiling_m = 2.5\ntour = [[1.0, 1.0], [1.0, 1.0]]\n'
            "[start]\nx = 1.0\ny = 1.0\nyaw = 0.0\n"
            "[[walls]]\nfrom = [0.0, 3.0]\nto = [3.0, 3.0]\n"
        )
        return [
            "sim", "--world", str(w), "--seconds", "1", "--width", "64", "--height", "48",
            "--calibration", "none", "--no-truth", "--out", str(d / "sim"),
        ]  # fmt: skip

    add(Case("sim_tour_equal_to_start", sim_tour_at_start, (EXIT_OK,)))
    add(
        Case(
            "sim_ten_hours_in_memory",
            lambda d, s: ["sim", "--seconds", "36000", "--out", str(d / "sim")],
            stderr_has="--max-memory-mb",
        )
    )

    # Output paths that cannot be written.
    def map_log_to(target: Callable[[Path], Path]):
        def build(d, s):
            return ["map-log", str(carmen_log(d / "l.log", None)), "-o", str(target(d))]

        return build

    def a_dir(d):
        (d / "m.yaml").mkdir()
        return d / "m.yaml"

    def read_only(d):
        (d / "ro").mkdir()
        os.chmod(d / "ro", 0o555)
        return d / "ro" / "m.yaml"

    def under_file(d):
        (d / "f").write_text("x")
        return d / "f" / "m.yaml"

    def too_long(d):
        return d / ("m" * 300 + ".yaml")

    for name, target in (
        ("dir", a_dir),
        ("read_only", read_only),
        ("under_file", under_file),
        ("too_long", too_long),
    ):
        skip_ro = name == "read_only" and os.geteuid() == 0
        if not skip_ro:
            add(Case(f"map_log_output_{name}", map_log_to(target), (EXIT_OS,)))

    def run_out_under_file(d, s):
        (d / "f").write_text("x")
        return run_args(s, s / "room", d / "f" / "out")

    add(Case("run_output_under_file", run_out_under_file, (EXIT_OS,)))

    def scan_out_dir(d, s):
        (d / "s.csv").mkdir()
        return ["scan", str(s / "room"), "--table", str(s / "table.json"), "-o", str(d / "s.csv")]

    add(Case("scan_output_dir", scan_out_dir, (EXIT_OS,)))

    # Damaged bags.
    def bag_file(content: bytes, suffix: str = ".bag"):
        def build(d, s):
            p = d / f"b{suffix}"
            p.write_bytes(content)
            return run_args(s, p, d / "out")

        return build

    add(Case("bag_empty_file", bag_file(b""), stderr_has="bag"))
    add(Case("bag_header_only", bag_file(b"#ROSBAG V2.0\n"), stderr_has="bag"))
    add(Case("bag_garbage", bag_file(b"#ROSBAG V2.0\n" + os.urandom(4000)), stderr_has="bag"))

    def ros2_bag(damage: str):
        def build(d, s):
            from floorscan.formats.dataset import read_images_txt
            from floorscan.formats.image_io import read_grey
            from floorscan.formats.rosbag import write_image_odometry_bag
            from floorscan.formats.trajectory import read_tum

            frames = [(e.timestamp, read_grey(e.path)) for e in read_images_txt(s / "room")]
            bag = write_image_odometry_bag(
                d / "bag", frames, read_tum(s / "room" / "odometry.txt"), ros_version=2
            )
            meta = bag / "metadata.yaml"
            data = [p for p in bag.iterdir() if p.suffix in (".db3", ".mcap")][0]
            if damage == "metadata":
                meta.write_text("rosbag2_bagfile_information: [unclosed\n")
            elif damage == "truncated":
                raw = data.read_bytes()
                data.write_bytes(raw[: len(raw) // 3])
            elif damage == "corrupt":
                raw = bytearray(data.read_bytes())
                for i in range(100, len(raw), 97):
                    raw[i] ^= 0x5A
                data.write_bytes(bytes(raw))
            elif damage == "empty_data":
                data.write_bytes(b"")
            return run_args(s, bag, d / "out")

        return build

    for damage in ("metadata", "truncated", "corrupt", "empty_data"):
        add(
            Case(
                f"ros2_bag_{damage}",
                ros2_bag(damage),
                (EXIT_OK, EXIT_ERROR),
                needs=("rosbags",),
            )
        )

    # Decompression bombs.
    def bomb_in_dataset(d, s):
        ds = copy_dataset(s, d / "ds")
        (ds / "images" / "000003.png").write_bytes(png_claiming(40000, 40000))
        return run_args(s, ds, d / "out")

    def one_skipped(d):
        counts = json.loads((d / "out" / "summary.json").read_text())["counts"]
        assert counts["skipped_unreadable"] == 1, counts

    add(Case("run_dataset_png_bomb", bomb_in_dataset, (EXIT_OK,), check=one_skipped))

    def bomb_overlay(d, s):
        (d / "b.png").write_bytes(png_claiming(30000, 30000))
        return [
            "overlay",
            str(d / "b.png"),
            "--table",
            str(s / "table.json"),
            "-o",
            str(d / "o.png"),
        ]

    add(Case("overlay_png_bomb", bomb_overlay, stderr_has="pixels"))

    # Files that are not UTF-8.
    latin1 = "# caf\xe9\n".encode("latin-1") + b"\xff\xfe\n"

    def not_utf8(name: str):
        def build(d, s):
            ds = copy_dataset(s, d / "ds")
            if name == "config":
                (d / "c.toml").write_bytes(latin1)
                return run_args(s, ds, d / "out", "--config", str(d / "c.toml"))
            target = ds / name
            target.write_bytes(latin1 + target.read_bytes())
            return run_args(s, ds, d / "out")

        return build

    for name in ("config", "images.txt", "odometry.txt", "rig.toml"):
        add(Case(f"not_utf8_{name}", not_utf8(name)))

    def config_check_not_utf8(d, s):
        (d / "c.toml").write_bytes(latin1)
        return ["config", "--check", str(d / "c.toml")]

    add(Case("config_check_not_utf8", config_check_not_utf8))

    # Garbage that used to be accepted.
    def zero_quaternion(d, s):
        ds = copy_dataset(s, d / "ds")
        lines = (ds / "odometry.txt").read_text().splitlines()
        parts = lines[3].split()
        parts[4:8] = ["0", "0", "0", "0"]
        lines[3] = " ".join(parts)
        (ds / "odometry.txt").write_text("\n".join(lines) + "\n")
        return run_args(s, ds, d / "out")

    add(Case("odometry_zero_quaternion", zero_quaternion, stderr_has="quaternion"))

    def images_not_monotonic(d, s):
        ds = copy_dataset(s, d / "ds")
        lines = (ds / "images.txt").read_text().splitlines()
        lines[2], lines[3] = lines[3], lines[2]
        (ds / "images.txt").write_text("\n".join(lines) + "\n")
        return run_args(s, ds, d / "out")

    add(Case("images_txt_not_monotonic", images_not_monotonic, stderr_has="increasing"))

    def corrupt_gzip_log(d, s):
        import gzip

        data = gzip.compress(b"FLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0\n" * 200)
        (d / "l.log.gz").write_bytes(data[: len(data) // 2] + b"\x00garbage")
        return ["map-log", str(d / "l.log.gz"), "-o", str(d / "m.yaml")]

    add(Case("map_log_gzip_damaged_midway", corrupt_gzip_log, stderr_has="cannot read CARMEN log"))

    def hdr_in_bag(d, s):
        import cv2
        import numpy as np
        from floorscan.formats.dataset import read_images_txt
        from floorscan.formats.image_io import read_grey
        from floorscan.formats.rosbag import write_image_odometry_bag
        from floorscan.formats.trajectory import read_tum

        entries = read_images_txt(s / "room")
        frames = [(e.timestamp, read_grey(e.path)) for e in entries]
        frames[2] = (frames[2][0], np.zeros((1, 1), np.uint8))  # marks the HDR frame
        real = cv2.imencode
        hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 30000 +X 30000\n" + b"\x02\x02" * 64

        def encode(ext, img, *a):
            if img.shape == (1, 1):
                return True, np.frombuffer(hdr, np.uint8)
            return real(ext, img, *a)

        cv2.imencode = encode
        try:
            write_image_odometry_bag(
                d / "bag", frames, read_tum(s / "room" / "odometry.txt"), compressed=True
            )
        finally:
            cv2.imencode = real
        return run_args(s, d / "bag", d / "out")

    add(
        Case(
            "run_bag_with_30000px_radiance_hdr",
            hdr_in_bag,
            (EXIT_OK,),
            check=bomb_checked,
            needs=("rosbags",),
        )
    )

    def start_in_wall(d, s):
        w = d / "w.toml"
        w.write_text(
            'name = "stuck"\ntour = [[1.0, 1.0], [2.0, 1.0]]\n'
            "[start]\nx = 1.5\ny = 3.0\nyaw = 0.0\n"
            "[[walls]]\nfrom = [0.0, 3.0]\nto = [3.0, 3.0]\n"
        )
        return ["sim", "--world", str(w), "--seconds", "1", "--out", str(d / "sim")]

    add(Case("sim_start_inside_a_wall", start_in_wall, stderr_has="start pose"))

    def columns_vs_table(d, s):
        c = config_file(d, "[ranger]\ncolumns = 100000\n")
        return ["config", "--check", str(c), "--table", str(s / "table.json")]

    add(Case("config_check_columns_wider_than_the_table", columns_vs_table, stderr_has="columns"))

    for key, text in BAD_CONFIGS.items():

        def bad_run(d, s, text=text):
            return run_args(s, s / "room", d / "out", "--config", str(config_file(d, text)))

        def bad_check(d, s, text=text):
            return ["config", "--check", str(config_file(d, text))]

        add(Case(f"config_run_{key}", bad_run, check=lambda d: _no_outputs(d / "out")))
        add(Case(f"config_check_{key}", bad_check))
    return cases


def _no_outputs(out: Path) -> None:
    assert not out.exists() or not any(out.iterdir()), sorted(p.name for p in out.iterdir())


CASES = _cases()


# --- running ------------------------------------------------------------------------------


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT_BYTES, MEMORY_LIMIT_BYTES))


def temp_files(folder: Path) -> List[str]:
    """Temporary files and folders a writer left (floorscan's start with a dot)."""
    return sorted(
        str(p.relative_to(folder))
        for p in folder.rglob(".*")
        if p.name not in (".", "..") and not p.name.startswith(".pytest")
    )


def run_case(case: Case, folder: Path, shared: Path, timeout_s: float = TIMEOUT_S) -> Result:
    folder.mkdir(parents=True, exist_ok=True)
    argv = case.build(folder, shared)
    t0 = time.perf_counter()
    proc = subprocess.Popen(
        [FLOORSCAN, *argv],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        preexec_fn=_limit_memory,
        cwd=folder,
    )
    hang = False
    deadline = t0 + timeout_s
    rc: Optional[int] = None
    usage = None
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            rc = os.waitstatus_to_exitcode(status)
            break
        if time.perf_counter() > deadline:
            hang = True
            proc.send_signal(signal.SIGKILL)
            _, status, usage = os.wait4(proc.pid, 0)
            break
        time.sleep(0.02)
    proc.returncode = rc
    stderr = proc.stderr.read().decode("utf-8", "replace")
    proc.stderr.close()
    if (folder / "ro").exists():
        os.chmod(folder / "ro", 0o755)
    return Result(
        name=case.name,
        rc=rc,
        stderr=stderr,
        peak_rss_mb=usage.ru_maxrss / 1024.0 if usage else math.nan,
        seconds=time.perf_counter() - t0,
        hang=hang,
        temp_files=temp_files(folder),
    )


def make_shared(folder: Path, frames: int = 8) -> Path:
    sys.path.insert(0, str(Path(__file__).parent))
    from synthetic_dataset import camera_table, make_dataset

    folder.mkdir(parents=True, exist_ok=True)
    if not (folder / "room" / "images.txt").is_file():
        make_dataset(folder / "room", n=frames)
        camera_table().save(folder / "table.json")
    return folder
