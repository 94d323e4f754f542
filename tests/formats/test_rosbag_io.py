"""ROS 1 and ROS 2 bags written with rosbags are read back: images, odometry, scans, maps."""

from __future__ import annotations

from types import SimpleNamespace

import cv2
import floorscan
import numpy as np
import pytest
from floorscan.formats.rosbag import (
    ROSBAGS_MISSING,
    Ros2BagWriter,
    bag_topics,
    decode_image,
    iter_bag_images,
    read_bag_odometry,
    write_image_odometry_bag,
)
from floorscan.formats.trajectory import Trajectory

pytest.importorskip("rosbags", reason=ROSBAGS_MISSING)


def frames(n=3, h=24, w=32):
    rng = np.random.default_rng(1)
    return [(10.0 + 0.1 * i, rng.integers(0, 256, size=(h, w), dtype=np.uint8)) for i in range(n)]


ODOM = Trajectory(
    [9.95, 10.05, 10.15, 10.25], [0.0, 0.1, 0.2, 0.3], [0.0, 0.0, 0.01, 0.02], [0.0, 0.1, -3.1, 3.1]
)


@pytest.mark.parametrize("ros_version,name", [(1, "test.bag"), (2, "test_bag")])
@pytest.mark.parametrize("compressed", [False, True])
def test_images_and_odometry_round_trip(tmp_path, ros_version, name, compressed):
    fr = frames()
    path = write_image_odometry_bag(
        tmp_path / name, fr, ODOM, ros_version=ros_version, compressed=compressed
    )
    topics = bag_topics(path)
    assert topics["/odom"] == "nav_msgs/msg/Odometry"
    got = list(iter_bag_images(path, image_topic="/camera/image_raw"))
    assert [t for t, _, _ in got] == pytest.approx([t for t, _ in fr])
    assert [e for _, _, e in got] == [None] * len(fr)
    for (_, a, _), (_, b) in zip(got, fr):
        np.testing.assert_array_equal(a, b)
    odo = read_bag_odometry(path, odom_topic="/odom")
    np.testing.assert_allclose(odo.x, ODOM.x)
    np.testing.assert_allclose(np.cos(odo.yaw - ODOM.yaw), 1.0, atol=1e-9)


def test_missing_topic_and_missing_bag_are_dataset_errors(tmp_path):
    path = write_image_odometry_bag(tmp_path / "b", frames(1), ODOM, ros_version=2)
    with pytest.raises(floorscan.DatasetError, match="no topic '/camera'"):
        list(iter_bag_images(path, image_topic="/camera"))
    with pytest.raises(floorscan.DatasetError, match="expected"):
        list(iter_bag_images(path, image_topic="/odom"))
    with pytest.raises(floorscan.DatasetError, match="not found"):
        read_bag_odometry(tmp_path / "nope", odom_topic="/odom")


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_laser_scans_and_maps_are_written_and_read_back(tmp_path, storage):
    from rosbags.highlevel import AnyReader

    w = Ros2BagWriter(tmp_path / "out", storage=storage)
    laser = dict(
        angle_min=-0.5,
        angle_max=0.5,
        angle_increment=0.5,
        range_min=0.1,
        range_max=3.0,
        ranges=np.array([1.0, np.inf, 2.5]),
    )
    w.write_laser_scan(1.5, laser)
    grid = np.array([[-1, 0, 100], [50, -1, 0]], dtype=np.int8)
    w.write_occupancy_grid(2.0, grid, resolution_m=0.04, origin_xy_yaw=(-1.0, -2.0, 0.0))
    path = w.close()
    with AnyReader([path]) as reader:
        msgs = {c.topic: reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages()}
    np.testing.assert_array_equal(msgs["/scan"].ranges, np.array([1.0, np.inf, 2.5], np.float32))
    assert msgs["/scan"].header.stamp.sec == 1 and msgs["/scan"].header.stamp.nanosec == 500_000_000
    m = msgs["/map"]
    assert (m.info.width, m.info.height) == (3, 2) and m.info.resolution == pytest.approx(0.04)
    np.testing.assert_array_equal(m.data.reshape(2, 3), grid)
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_negative_times_are_refused_before_any_file_is_written(tmp_path):
    with pytest.raises(floorscan.DatasetError, match=">= 0"):
        write_image_odometry_bag(
            tmp_path / "neg", [(-1.0, np.zeros((4, 4), np.uint8))], ODOM, ros_version=2
        )
    assert not (tmp_path / "neg").exists()


def test_a_compressed_image_whose_size_cannot_be_checked_is_refused_undecoded():
    """A Radiance HDR (or EXR, PFM) message: OpenCV decodes it whole whatever its declared
    size (3.5 GB from a 9 MB message), PIL cannot read its header; it is refused before any
    decoding, in one line. A PNG or JPEG over the pixel limit is refused by its header."""
    hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 30000 +X 30000\n" + b"\x02\x02\x75\x30" * 64
    msg = SimpleNamespace(data=hdr, format="hdr")
    with pytest.raises(floorscan.ImageError, match="size cannot be checked before decoding") as e:
        decode_image(msg, "sensor_msgs/msg/CompressedImage")
    assert "\n" not in str(e.value)
    # a small HDR OpenCV would decode is refused all the same (its size is not known first)
    ok, small = cv2.imencode(".hdr", np.ones((4, 4, 3), np.float32))
    assert ok
    with pytest.raises(floorscan.ImageError, match="cannot be checked"):
        decode_image(
            SimpleNamespace(data=small.tobytes(), format="hdr"), "sensor_msgs/msg/CompressedImage"
        )
    # PNG keeps working
    ok, png = cv2.imencode(".png", np.full((6, 8), 7, np.uint8))
    out = decode_image(
        SimpleNamespace(data=png.tobytes(), format="png"), "sensor_msgs/msg/CompressedImage"
    )
    assert out.shape == (6, 8) and int(out[0, 0]) == 7


@pytest.mark.parametrize("ext", [".png", ".jpg"])
def test_a_compressed_image_the_decoder_complains_about_is_an_error(capfd, ext):
    """A damaged PNG (CRC) or a JPEG cut short: OpenCV's decoders print their complaint and
    may still return pixels (a cut JPEG comes back "whole", grey where data was missing). The
    complaint is the message's ImageError (the frame is skipped and counted), not raw stderr."""
    img = np.random.default_rng(3).integers(0, 255, (48, 64), np.uint8)
    data = bytearray(cv2.imencode(ext, img)[1].tobytes())
    if ext == ".png":
        data[60] ^= 0xFF  # inside the image data: the chunk's CRC no longer matches
    else:
        data = data[: len(data) * 2 // 3] + b"\xff\xd9"  # cut, with its end marker
    assert decode_image(
        SimpleNamespace(data=cv2.imencode(ext, img)[1].tobytes(), format=ext[1:]),
        "sensor_msgs/msg/CompressedImage",
    ).shape == (48, 64)
    capfd.readouterr()
    with pytest.raises(floorscan.ImageError, match="cannot decode compressed image .*: .+"):
        decode_image(
            SimpleNamespace(data=bytes(data), format=ext[1:]), "sensor_msgs/msg/CompressedImage"
        )
    assert capfd.readouterr().err == ""
    # the live node leaves stderr alone (its transport's threads log there): the decoder's
    # own words reach it, and whatever the decoder returns is taken
    try:
        decode_image(
            SimpleNamespace(data=bytes(data), format=ext[1:]),
            "sensor_msgs/msg/CompressedImage",
            catch_decoder=False,
        )
    except floorscan.ImageError as e:  # nothing decoded at all
        assert str(e).endswith(f"(format {ext[1:]!r})")
    assert capfd.readouterr().err != ""
