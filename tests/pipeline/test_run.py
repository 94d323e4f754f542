"""`floorscan run` end to end on a small synthetic dataset: every output exists and parses, the
bag's LaserScans equal the CSV, the map agrees with the true room, skips are counted, strict
mode fails, and Ctrl-C leaves a loadable map."""

from __future__ import annotations

import json
import os
import signal

import floorscan
import numpy as np
import pytest
from floorscan import OccupancyGrid, read_scans_csv
from floorscan.cli import main
from floorscan.formats.rosbag import ROSBAGS_MISSING
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import Mapper, run
from floorscan.pipeline.outputs import RunOutputs
from floorscan.pipeline.sources import DatasetSource
from synthetic_dataset import camera_table, make_dataset, true_occupied


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("ds")
    make_dataset(d / "room", n=30)
    camera_table().save(d / "table.json")
    return d


def test_run_writes_every_output_and_the_map_matches_the_room(dataset, tmp_path):
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)  # the bag among the outputs
    out = tmp_path / "out"
    rc = main(
        [
            "run",
            str(dataset / "room"),
            "--table",
            str(dataset / "table.json"),
            "-o",
            str(out),
            "--threshold",
            "20",
        ]
    )
    assert rc == 0
    for name in (
        "map.yaml",
        "map.pgm",
        "map.png",
        "scans.csv",
        "summary.json",
        "overlay.gif",
        "local/local_final.png",
    ):
        assert (out / name).is_file(), name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["counts"]["frames_mapped"] == 30
    scans = read_scans_csv(out / "scans.csv")
    # the default columns: placed on this camera's table (no 3 cm obstacle at 1 m between two)
    columns = floorscan.VisualRanger(floorscan.GroundTable.load(dataset / "table.json")).columns
    assert len(scans) == 30 and all(np.array_equal(s.columns, columns) for s in scans)
    # The bag's LaserScans are the CSV scans binned.
    from rosbags.highlevel import AnyReader

    with AnyReader([out / "bag"]) as reader:
        lasers = [
            reader.deserialize(raw, c.msgtype)
            for c, _, raw in reader.messages()
            if c.topic == "/scan"
        ]
    assert len(lasers) == 30
    for laser, scan in zip(lasers, scans):
        ref = scan.to_laser_scan(
            angle_min=laser.angle_min,
            angle_max=laser.angle_max,
            angle_increment=laser.angle_increment,
        )
        np.testing.assert_allclose(laser.ranges, np.asarray(ref["ranges"], np.float32), rtol=1e-6)
    # The map, built with exact poses, agrees with the room on at least 95% of its known cells.
    grid = OccupancyGrid.load(out / "map.yaml")
    classes = grid.occupancy_classes()  # 0 free, 1 unknown, 2 occupied (rows from the bottom)
    ext = grid.extent
    cell = grid.cell_size_m
    ys, xs = np.mgrid[0 : classes.shape[0], 0 : classes.shape[1]]
    cx = ext.origin_m[0] + (xs + 0.5) * cell
    cy = ext.origin_m[1] + (ys + 0.5) * cell
    known = classes != 1
    truth = true_occupied(cx, cy, cell)
    agree = (classes == 2) == truth
    assert known.sum() > 500
    assert agree[known].mean() >= 0.95


class InterruptingSource(DatasetSource):
    """Sends a real SIGINT to this process at frame `at`."""

    def __init__(self, folder, at):
        super().__init__(folder)
        self.at = at

    def __iter__(self):
        for f in super().__iter__():
            if f.index == self.at:
                os.kill(os.getpid(), signal.SIGINT)
            yield f


def test_ctrl_c_still_leaves_a_loadable_map(dataset, tmp_path):
    cfg = Config()
    mapper = Mapper(floorscan.GroundTable.load(dataset / "table.json"), cfg)
    outputs = RunOutputs(tmp_path / "out", cfg)
    stats = run(InterruptingSource(dataset / "room", at=10), mapper, outputs)
    assert stats.interrupted and 9 <= stats.frames_mapped <= 11
    grid = OccupancyGrid.load(tmp_path / "out" / "map.yaml")
    assert (grid.occupancy_classes() != 1).sum() > 0
    assert len(read_scans_csv(tmp_path / "out" / "scans.csv")) == stats.frames_mapped


def test_frames_outside_the_odometry_are_skipped_and_counted(dataset, tmp_path):
    ds = tmp_path / "short"
    make_dataset(ds, n=12)
    lines = (ds / "odometry.txt").read_text().splitlines()
    (ds / "odometry.txt").write_text("\n".join(lines[:8]) + "\n")  # header + 7 poses: t <= 0.55
    out = tmp_path / "out"
    assert main(["run", str(ds), "--table", str(dataset / "table.json"), "-o", str(out)]) == 0
    counts = json.loads((out / "summary.json").read_text())["counts"]
    assert counts["frames_in"] == 12
    assert counts["skipped_no_odometry"] == 12 - 6  # frames at t = 100.0 .. 100.5 are covered
    assert (
        main(
            [
                "run",
                str(ds),
                "--table",
                str(dataset / "table.json"),
                "-o",
                str(tmp_path / "strict"),
                "--strict",
            ]
        )
        == 1
    )


def test_unreadable_and_wrong_size_frames_are_counted(dataset, tmp_path):
    ds = tmp_path / "broken"
    make_dataset(ds, n=6)
    (ds / "images" / "000002.png").write_bytes(b"\x89PNG truncated")
    from floorscan.formats.image_io import write_png

    write_png(ds / "images" / "000004.png", np.zeros((10, 10), np.uint8))
    out = tmp_path / "out"
    assert main(["run", str(ds), "--table", str(dataset / "table.json"), "-o", str(out)]) == 0
    counts = json.loads((out / "summary.json").read_text())["counts"]
    assert (
        counts["skipped_unreadable"] == 1
        and counts["skipped_wrong_size"] == 1
        and counts["frames_mapped"] == 4
    )
    assert (
        main(
            [
                "run",
                str(ds),
                "--table",
                str(dataset / "table.json"),
                "-o",
                str(tmp_path / "s"),
                "--strict",
            ]
        )
        == 1
    )


@pytest.mark.parametrize("ros_version", [1, 2])
def test_bags_are_read_and_mapped(dataset, tmp_path, ros_version):
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)
    from floorscan.formats.rosbag import write_image_odometry_bag

    src = DatasetSource(dataset / "room")
    frames = [(f.timestamp, f.image) for f in src][:10]
    bag = tmp_path / ("in.bag" if ros_version == 1 else "in_bag")
    write_image_odometry_bag(
        bag, frames, src.odometry, ros_version=ros_version, compressed=ros_version == 2
    )
    out = tmp_path / "out"
    assert main(["run", str(bag), "--table", str(dataset / "table.json"), "-o", str(out)]) == 0
    counts = json.loads((out / "summary.json").read_text())["counts"]
    assert counts["frames_mapped"] == 10
    missing = main(
        [
            "run",
            str(bag),
            "--table",
            str(dataset / "table.json"),
            "-o",
            str(tmp_path / "o2"),
            "--image-topic",
            "/nope",
        ]
    )
    assert missing == 1


def test_calibration_for_another_resolution_is_skipped_or_fails(dataset, tmp_path):
    floorscan.GroundTable.from_function(
        lambda u, v: (u * 0 + 1.0, v * 0), image_width=40, image_height=30, spacing_px=4
    ).save(tmp_path / "t.json")
    assert (
        main(
            [
                "run",
                str(dataset / "room"),
                "--table",
                str(tmp_path / "t.json"),
                "-o",
                str(tmp_path / "o"),
                "--strict",
            ]
        )
        == 1
    )


def test_automatic_threshold_follows_the_texture_noise(dataset, tmp_path):
    """With ranger.auto_threshold the run's threshold is k x the robust noise of the filter
    response in the rows nearest the robot, estimated on the first frame. The synthetic room's
    floor noise is Gaussian with sigma 2 per pixel (rounded to integers)."""
    from floorscan.formats.image_io import read_grey
    from floorscan.ranging.auto_threshold import texture_noise

    cfg = Config().with_overrides({"ranger.auto_threshold": True, "ranger.auto_threshold_k": 4.0})
    table = floorscan.GroundTable.load(dataset / "table.json")
    mapper = Mapper(table, cfg)
    first = read_grey(dataset / "room" / "images" / "000000.png")
    mapper.process(first, timestamp=100.0, pose=(0.0, 0.0, 0.0))
    noise = texture_noise([first], half_width=4, columns=mapper.ranger.columns, bottom_margin=2)
    assert mapper.texture_noise == pytest.approx(noise)
    assert mapper.threshold == pytest.approx(max(4.0 * noise, 2.0))
    edge_options = mapper.ranger.options.get("edge", mapper.ranger.options)  # fused or edge
    assert edge_options["threshold"] == pytest.approx(mapper.threshold)
    # White noise of sigma 2 per pixel: R = (sum of 4 - sum of 4) / 8 has sigma 2 * sqrt(8) / 8.
    assert noise == pytest.approx(2.0 * np.sqrt(8) / 8, rel=0.25)


def test_video_with_an_odometry_file_is_mapped(dataset, tmp_path):
    import cv2

    src = DatasetSource(dataset / "room")
    frames = [f.image for f in src][:12]
    h, w = frames[0].shape
    video = tmp_path / "in.avi"
    vw = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"MJPG"), 10.0, (w, h), isColor=False)
    assert vw.isOpened()
    for f in frames:
        vw.write(f)
    vw.release()
    # The video's clock starts at 0; shift the odometry to it (frames at 0.0, 0.1, ...).
    from floorscan.formats.trajectory import Trajectory, write_tum

    odo = src.odometry
    write_tum(tmp_path / "odo.txt", Trajectory(odo.timestamps - 100.0, odo.x, odo.y, odo.yaw))
    out = tmp_path / "out"
    assert (
        main(
            [
                "run",
                str(video),
                "--odometry",
                str(tmp_path / "odo.txt"),
                "--table",
                str(dataset / "table.json"),
                "-o",
                str(out),
            ]
        )
        == 0
    )
    counts = json.loads((out / "summary.json").read_text())["counts"]
    assert counts["frames_in"] == 12 and counts["frames_mapped"] == 12
    assert (OccupancyGrid.load(out / "map.yaml").occupancy_classes() == 2).sum() > 0


def test_rust_png_decoding_gives_the_outputs_of_pillow_decoding_byte_for_byte(
    dataset, tmp_path, monkeypatch
):
    """The decoder changed (Rust instead of Pillow): every output is byte-identical to the old
    path's (scans CSV, the bag's messages, the maps), and the streamed overlay GIF holds the
    palette-indexed overlays of the kept frames."""
    pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)
    from floorscan.formats import image_io
    from floorscan.pipeline import sources
    from floorscan.pipeline.outputs import OVERLAY_MAX_WIDTH
    from floorscan.ranging.overlay import OVERLAY_PALETTE, draw_scan_overlay_indexed
    from PIL import Image, ImageSequence
    from rosbags.highlevel import AnyReader

    args = ["run", str(dataset / "room"), "--table", str(dataset / "table.json")]
    args += ["--threshold", "20", "-o"]
    assert main([*args, str(tmp_path / "rust")]) == 0
    monkeypatch.setattr(sources, "read_grey", image_io._read_grey_pillow)
    assert main([*args, str(tmp_path / "pillow")]) == 0
    for name in ("scans.csv", "map.pgm", "map.yaml", "map.png", "overlay.gif"):
        assert (tmp_path / "rust" / name).read_bytes() == (tmp_path / "pillow" / name).read_bytes()

    def messages(out):
        with AnyReader([out / "bag"]) as reader:
            return [(c.topic, t, bytes(raw)) for c, t, raw in reader.messages()]

    assert messages(tmp_path / "rust") == messages(tmp_path / "pillow")
    scans = read_scans_csv(tmp_path / "rust" / "scans.csv")
    images = sorted((dataset / "room" / "images").iterdir())
    with Image.open(tmp_path / "rust" / "overlay.gif") as gif:
        got = [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(gif)]
    assert len(got) == len(scans)  # 30 frames, fewer than overlay_max_frames: all kept
    for k in (0, 17, 29):
        grey = image_io._read_grey_pillow(images[k])
        want = draw_scan_overlay_indexed(grey, scans[k], max_width=OVERLAY_MAX_WIDTH)
        np.testing.assert_array_equal(got[k], OVERLAY_PALETTE[want])


class _BagSignallingOnAbort:
    """Wraps the run's bag: its abort is where a third signal of a burst lands."""

    def __init__(self, bag):
        self.bag = bag

    def abort(self):
        os.kill(os.getpid(), signal.SIGTERM)
        self.bag.abort()


class _OutputsAbandonedWhileSaving(RunOutputs):
    """Two signals while the map is saved (the second abandons the rest), a third while the
    abandoned outputs are cleaned up."""

    def _finish_map(self, mapper):
        self._bag = _BagSignallingOnAbort(self._bag)
        os.kill(os.getpid(), signal.SIGTERM)
        os.kill(os.getpid(), signal.SIGTERM)
        super()._finish_map(mapper)


def test_a_signal_during_the_clean_up_of_abandoned_outputs_leaves_no_temporary_file(
    dataset, tmp_path, monkeypatch
):
    monkeypatch.setattr(floorscan._signals, "_ABANDONED", None)
    cfg = Config()
    mapper = Mapper(floorscan.GroundTable.load(dataset / "table.json"), cfg)
    out = tmp_path / "out"
    outputs = _OutputsAbandonedWhileSaving(out, cfg)
    with pytest.raises(KeyboardInterrupt):
        run(DatasetSource(dataset / "room"), mapper, outputs)
    assert mapper.frames == 30  # the run itself finished; only the saving was abandoned
    assert sorted(p.name for p in out.iterdir() if p.name.startswith(".")) == []
    assert not (out / "overlay.gif").exists()
