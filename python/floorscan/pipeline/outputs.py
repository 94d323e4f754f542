"""Everything ``floorscan run`` writes into its output folder, written as the run goes and
finalised (atomically, file by file) at the end, on Ctrl-C and on error:

- ``map.yaml`` + ``map.pgm`` (ROS map_server) and ``map.png``: the global map;
- ``map.evidence.npz``: its unclamped evidence, for exact merges (evidence.py);
- ``local/local_<t>.png``: local map snapshots every N seconds (the paper's Fig. 2);
- ``scans.csv``: every scan in the public CSV format;
- ``bag/``: a ROS 2 bag with ``/scan`` (sensor_msgs/LaserScan) and ``/map``
  (nav_msgs/OccupancyGrid);
- ``overlay.gif`` (or ``.mp4``): frames with the boundary points circled (Fig. 1b);
- ``trajectory.tum`` and ``trajectory_odometry.tum`` (with odometry and ``[slam] mode =
  "local"``): the poses the scans were inserted at (odometry corrected by local scan
  matching) and the odometry poses of the same frames, TUM format (docs/formats.md);
- ``summary.json``: counts, per-stage timings, the configuration used; ``slam``: frames
  matched and not, the final correction.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import List, Optional

import numpy as np

from .._atomic import _make_readable, deferred_signals, write_atomic
from ..errors import OptionError, OutputError
from ..formats.gif import GifWriter
from ..formats.rosbag import ROSBAGS_MISSING, Ros2BagWriter, rosbags_installed
from ..formats.trajectory import write_tum
from ..ranging.overlay import OVERLAY_PALETTE, draw_scan_overlay, draw_scan_overlay_indexed
from ..ranging.scan import SCAN_CSV_HEADER, Scan
from .config import Config


def _proc_status_mb(key: str) -> Optional[float]:
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(key):
                return round(int(line.split()[1]) / 1024, 1)
    except OSError:
        pass
    return None


def resident_mb() -> Optional[float]:
    """Resident memory of this process [MB] (Linux; None elsewhere)."""
    return _proc_status_mb("VmRSS:")


def peak_resident_mb() -> Optional[float]:
    """Peak resident memory of this process [MB] (Linux; None elsewhere)."""
    return _proc_status_mb("VmHWM:")


OVERLAY_FORMATS = ("gif", "mp4", "none")
BAG_STORAGES = ("mcap", "sqlite3")
OVERLAY_MAX_WIDTH = 480
"""Overlay frames wider than this [px] are halved (until they are not)."""
MIN_LASER_INCREMENT_RAD = 1e-4
"""Finest LaserScan bin (at most 62 832 bins over a full turn)."""


def _bad(key: str, why: str, value) -> OptionError:
    return OptionError(f"invalid option `outputs.{key}`: {why}, got {value!r}")


def check_outputs(o) -> None:
    """The ``[outputs]`` options' ranges (OptionError naming the key)."""
    if o.overlay not in OVERLAY_FORMATS:
        raise _bad("overlay", f"expected one of {', '.join(OVERLAY_FORMATS)}", o.overlay)
    if o.bag_storage not in BAG_STORAGES:
        raise _bad("bag_storage", f"expected one of {', '.join(BAG_STORAGES)}", o.bag_storage)
    if not 1 <= o.overlay_max_frames <= 100_000:
        raise _bad("overlay_max_frames", "must be in 1..=100000", o.overlay_max_frames)
    if not 1 <= o.overlay_max_mb <= 65_536:
        raise _bad("overlay_max_mb", "must be in 1..=65536 [MB]", o.overlay_max_mb)
    p = o.local_snapshot_period_s
    if not (math.isfinite(p) and p >= 0):
        raise _bad("local_snapshot_period_s", "must be finite and >= 0 (0 disables)", p)
    inc = o.laser_angle_increment_rad
    if not (math.isfinite(inc) and MIN_LASER_INCREMENT_RAD <= inc <= math.pi):
        raise _bad("laser_angle_increment_rad", "must be in [1e-4, pi] rad", inc)


RUN_OUTPUT_NAMES = (
    "scans.csv",
    "map.yaml",
    "map.pgm",
    "map.png",
    "map.evidence.npz",
    "summary.json",
    "overlay.gif",
    "overlay.mp4",
    "bag",
    "trajectory.tum",
    "trajectory_odometry.tum",
)
"""The files (and the bag folder) a run writes at the top of its output folder."""

_STALE = re.compile(
    r"^\.("
    + "|".join(re.escape(n) for n in RUN_OUTPUT_NAMES)
    + r")\.[a-z0-9_]{8}(\.(tmp|gif|mp4|png|npz|csv|yaml|pgm|json|tum))?$"
)
_STALE_LOCAL = re.compile(r"^\.local_([0-9]+\.[0-9]{2}|final)\.png\.[a-z0-9_]{8}\.png$")
"""The temporaries of the local map snapshots a run writes in ``local/``."""


def _write_marker(path: Path, text: str) -> None:
    """The "not complete" summary, written whole (a temporary renamed over it) but without
    holding signals back: it is written while a stop signal held through the start-up imports
    may still be waiting, and a stop here leaves at most a temporary that the next run into
    the folder removes (:func:`remove_stale_temporaries`)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        _make_readable(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def remove_stale_temporaries(out: Path) -> int:
    """Removes the temporary files (and bag folders) an earlier run into ``out`` left when it
    was killed before it could clean up (SIGKILL, a power cut): only the names a run's atomic
    writes use (``.scans.csv.x1y2z3ab``, ``.bag.x1y2z3ab/``, ``.map.yaml.x1y2z3ab.tmp``),
    only in ``out`` itself and its ``local/`` snapshot folder
    (``local/.local_0000105.00.png.x1y2z3ab.png``). Returns how many."""
    removed = 0
    local = out / "local"
    candidates = [p for p in out.iterdir() if _STALE.match(p.name)]
    if local.is_dir() and not local.is_symlink():
        candidates += [p for p in local.iterdir() if _STALE_LOCAL.match(p.name)]
    for p in candidates:
        try:
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink()
            removed += 1
        except OSError:
            pass  # another user's file, or gone already: not ours to insist on
    return removed


class RunOutputs:
    def __init__(self, out_dir, cfg: Config, *, expected_frames: Optional[int] = None) -> None:
        check_outputs(cfg.outputs)
        self.out = Path(out_dir)
        try:
            self.out.mkdir(parents=True, exist_ok=True)
        except FileExistsError:
            raise OutputError(f"output folder {self.out} exists and is not a folder") from None
        except OSError as e:
            raise OutputError(f"cannot create output folder {self.out}: {e.strerror}") from None
        if not os.access(self.out, os.W_OK | os.X_OK):
            raise OutputError(f"output folder {self.out} is not writable")
        self.stale_removed = remove_stale_temporaries(self.out)
        self.cfg = cfg
        self.finishing = False
        self._bag = None
        self._gif: Optional[GifWriter] = None
        self._csv = None
        self._csv_tmp: Optional[str] = None
        self._marker: Optional[str] = None
        try:
            # The folder says what it holds: "complete": false until the run's last output is
            # written (a run killed with SIGKILL leaves it so, and its outputs as they were).
            self._marker = json.dumps(
                {"complete": False, "started": time.time(), "pid": os.getpid()}, indent=2
            )
            _write_marker(self.out / "summary.json", self._marker)
            with deferred_signals():  # created and recorded together (see _discard_temporaries)
                fd, self._csv_tmp = tempfile.mkstemp(prefix=".scans.csv.", dir=self.out)
                self._csv = os.fdopen(fd, "w", encoding="utf-8")
            self._open(cfg, expected_frames)
        except BaseException:
            self._discard_temporaries()  # interrupted or failed while opening: leave nothing
            self._remove_marker()
            raise

    def _open(self, cfg: Config, expected_frames: Optional[int]) -> None:
        o = cfg.outputs
        _make_readable(self._csv_tmp)
        self._csv.write(SCAN_CSV_HEADER + "\n")
        # A GIF overlay is streamed: each kept frame is drawn in the indices of one palette and
        # encoded on a Rust thread as the run goes (formats/gif.py). MP4 frames live in one
        # buffer allocated (and touched) at the first frame, so memory stays flat over a run
        # however long. Frames wider than 480 px are halved.
        self._overlay: Optional[np.ndarray] = None
        self._overlay_n = 0
        self._overlay_cap = o.overlay_max_frames
        self._expected_frames = expected_frames
        self._overlay_every = (
            max(1, (expected_frames or 0) // max(o.overlay_max_frames, 1)) if expected_frames else 1
        )
        self._frame_count = 0
        self._next_snapshot: Optional[float] = None
        self.snapshots: List[Path] = []
        self._laser_range: Optional[tuple] = None
        self.extra_summary: dict = {}
        self.memory_samples: List[tuple] = []
        if o.bag and not rosbags_installed():
            # a missing optional part costs only its feature: the run goes on without the bag
            print(f"floorscan: no ROS 2 bag written: {ROSBAGS_MISSING}", file=sys.stderr)
            self.extra_summary["bag"] = f"not written: {ROSBAGS_MISSING}"
        elif o.bag:
            with deferred_signals():
                self._bag = Ros2BagWriter(self.out / "bag", storage=o.bag_storage)

    # --- per frame ----------------------------------------------------------------------
    def laser_angles(self, scan: Scan) -> tuple:
        """Fixed angular range of the LaserScan conversion, set from the first scan's columns."""
        if self._laser_range is None:
            inc = self.cfg.outputs.laser_angle_increment_rad
            b = scan.bearings[np.isfinite(scan.bearings)]
            lo, hi = (float(b.min()), float(b.max())) if b.size else (-0.5, 0.5)
            self._laser_range = (math.floor(lo / inc) * inc, math.ceil(hi / inc) * inc, inc)
        return self._laser_range

    def on_frame(self, frame, scan: Scan, pose, mapper) -> None:
        self.extra_summary["last_timestamp"] = scan.timestamp
        if pose is not None:
            self.extra_summary.setdefault("first_pose", list(pose))
        self._csv.write(scan.csv_lines())
        if self._bag is not None:
            lo, hi, inc = self.laser_angles(scan)
            self._bag.write_laser_scan(
                scan.timestamp, scan.to_laser_scan(angle_min=lo, angle_max=hi, angle_increment=inc)
            )
        o = self.cfg.outputs
        if (
            o.overlay != "none"
            and self._frame_count % self._overlay_every == 0
            and self._overlay_n < self._overlay_cap
        ):
            if o.overlay == "gif":
                self._stream_overlay(
                    draw_scan_overlay_indexed(frame.image, scan, max_width=OVERLAY_MAX_WIDTH)
                )
            else:
                self._keep_overlay(draw_scan_overlay(frame.image, scan))
        if self._frame_count % 600 == 0:
            self.memory_samples.append((self._frame_count, resident_mb()))
        self._frame_count += 1
        period = o.local_snapshot_period_s
        if period > 0:
            if self._next_snapshot is None:
                self._next_snapshot = scan.timestamp + period
            elif scan.timestamp >= self._next_snapshot:
                self.snapshot_local(mapper, scan.timestamp)
                self._next_snapshot += period * max(
                    1, math.floor((scan.timestamp - self._next_snapshot) / period) + 1
                )

    def _overlay_frames(self, rgb_nbytes: int) -> None:
        """At the first kept frame: how many frames the overlay keeps, and how often. Bounded
        by overlay_max_mb of RGB frames: fewer frames, spread over the run, when they are big."""
        o = self.cfg.outputs
        fit = max(1, (o.overlay_max_mb << 20) // max(rgb_nbytes, 1))
        self._overlay_cap = min(o.overlay_max_frames, fit)
        if self._expected_frames:
            self._overlay_every = max(1, self._expected_frames // self._overlay_cap)

    def _keep_overlay(self, rgb: np.ndarray) -> None:
        while rgb.shape[1] > OVERLAY_MAX_WIDTH:
            rgb = rgb[::2, ::2]
        if self._overlay is None:
            self._overlay_frames(rgb.nbytes)
            self._overlay = np.full((self._overlay_cap,) + rgb.shape, 0, dtype=np.uint8)
        self._overlay[self._overlay_n] = rgb
        self._overlay_n += 1

    def _stream_overlay(self, indices: np.ndarray) -> None:
        if self._gif is None:
            self._overlay_frames(3 * indices.nbytes)
            h, w = indices.shape
            with deferred_signals():  # the writer and its temporary file are never lost
                self._gif = GifWriter(
                    self.out / "overlay.gif",
                    width=w,
                    height=h,
                    palette=OVERLAY_PALETTE,
                    frame_s=0.1,
                )
        self._gif.add(indices)
        self._overlay_n += 1

    def snapshot_local(self, mapper, t: float) -> Path:
        path = self.out / "local" / f"local_{t:010.2f}.png"
        mapper.local_map.to_png(path)
        self.snapshots.append(path)
        return path

    # --- end of run ---------------------------------------------------------------------
    def finish(self, mapper, stats) -> None:
        """Writes every output. Each is written whole or not at all: a failing output does
        not stop the others (the first error is raised after them all), and an interrupt
        leaves no temporary file behind."""
        steps = [
            self._finish_scans,
            lambda: self._finish_map(mapper),
            lambda: self._write_trajectories(mapper),
            self._write_overlay,
            lambda: self._write_summary(mapper, stats),
        ]
        self.finishing = True
        first: Optional[BaseException] = None
        try:
            for step in steps:
                try:
                    step()
                except Exception as e:  # noqa: PERF203 - each output on its own
                    first = first or e
        except BaseException:
            self._discard_temporaries()
            raise
        self._discard_temporaries()
        if first is not None:
            raise first

    def _finish_scans(self) -> None:
        self._csv.close()
        os.replace(self._csv_tmp, self.out / "scans.csv")

    def _finish_map(self, mapper) -> None:
        grid = mapper.global_map
        grid.save(self.out / "map.yaml")
        grid.to_png(self.out / "map.png")
        grid.evidence(name=self.out.name).save(self.out / "map.evidence.npz")
        if mapper.frames:
            mapper.local_map.to_png(self.out / "local" / "local_final.png")
        if self._bag is not None:
            bag, self._bag = self._bag, None
            try:
                data, resolution, origin = grid.to_occupancy_grid()
                bag.write_occupancy_grid(
                    float(self.extra_summary.get("last_timestamp", 0.0)),
                    data,
                    resolution_m=resolution,
                    origin_xy_yaw=origin,
                )
                bag.close()
            except BaseException:
                bag.abort()
                raise

    def discard(self) -> None:
        """Abandons a run that never started: removes the temporary files (see finish) and
        the folder's "not complete" summary."""
        self._discard_temporaries()
        self._remove_marker()

    def _remove_marker(self) -> None:
        """Removes the "complete": false summary this run wrote, if it is still that one."""
        path = self.out / "summary.json"
        try:
            if self._marker is not None and path.read_text() == self._marker:
                path.unlink()
        except OSError:
            pass

    def _discard_temporaries(self) -> None:
        """Removes what an interrupted or failed finish left: the scans' temporary file, an
        unfinished bag, a half-written overlay. Signals are held back until all are removed
        (a burst of signals abandons the outputs and would otherwise interrupt this clean-up
        part way, leaving the rest behind)."""
        with deferred_signals():
            self._discard_held()

    def _discard_held(self) -> None:
        if self._csv is not None and not self._csv.closed:
            self._csv.close()
        if self._csv_tmp is not None:
            Path(self._csv_tmp).unlink(missing_ok=True)
        if self._bag is not None:
            bag, self._bag = self._bag, None
            try:
                bag.abort()
            except Exception:  # the temporary bag folder is removed either way
                pass
        if self._gif is not None:
            gif, self._gif = self._gif, None
            gif.abort()
        (self.out / ".overlay.tmp.mp4").unlink(missing_ok=True)

    def _write_overlay(self) -> None:
        o = self.cfg.outputs
        if self._gif is not None:
            # closed while still held, so that a signal between the two steps leaves it to
            # _discard_temporaries (aborting a closed writer is a no-op), not lost with its
            # temporary file
            self._gif.close()
            self._gif = None
            return
        if o.overlay == "none" or self._overlay is None or self._overlay_n == 0:
            return
        kept = self._overlay[: self._overlay_n]  # MP4: the GIF was streamed (_stream_overlay)
        import cv2

        h, w = kept[0].shape[:2]
        tmp = self.out / ".overlay.tmp.mp4"
        vw = cv2.VideoWriter(str(tmp), cv2.VideoWriter_fourcc(*"mp4v"), 10.0, (w, h))
        for f in kept:
            vw.write(np.ascontiguousarray(f[..., ::-1]))
        vw.release()
        os.replace(tmp, self.out / "overlay.mp4")

    def _write_trajectories(self, mapper) -> None:
        slam = getattr(mapper, "slam", None)
        if slam is None or not slam.counts.frames:
            return
        write_tum(self.out / "trajectory.tum", slam.corrected)
        write_tum(self.out / "trajectory_odometry.tum", slam.odometry)

    def _write_summary(self, mapper, stats) -> None:
        t = mapper.times
        n = max(mapper.frames, 1)
        summary = {
            "counts": stats.as_dict(),
            "timings_s": t.as_dict(),
            "ms_per_frame": {
                "ranging": 1e3 * t.ranging_s / n,
                "mapping": 1e3 * t.mapping_s / n,
                "decode": 1e3 * t.decode_s / max(stats.frames_in, 1),
            },
            "points_per_frame": mapper.points / n,
            "memory_mb": {"resident_by_frame": self.memory_samples, "peak": peak_resident_mb()},
            "outputs": sorted(
                str(p.relative_to(self.out))
                for p in self.out.rglob("*")
                if p.is_file() and not p.name.startswith(".")
            ),
            "config": self.cfg.to_dict(),
            "complete": True,
            "stale_temporaries_removed": self.stale_removed,
            "ranger_threshold": {
                "used": mapper.threshold,
                "texture_noise": mapper.texture_noise,
                "automatic": mapper.cfg.ranger.auto_threshold,
            },
            **self.extra_summary,
        }
        slam = getattr(mapper, "slam", None)
        summary["slam"] = {"mode": mapper.cfg.slam.mode}
        if slam is not None:
            summary["slam"].update(slam.summary())
            summary["ms_per_frame"]["matching"] = 1e3 * t.matching_s / n
        write_atomic(self.out / "summary.json", json.dumps(summary, indent=2, default=float))
