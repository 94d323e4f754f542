"""Known intrinsics read from OpenCV FileStorage and ROS camera_info files: the values come
back as written; a damaged file or values no camera has (a focal length of 1e-320 px, a
distortion coefficient of 1e308) are one FileFormatError naming the file, never an internal
error or an overflow later in the fit."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from floorscan.calibration.intrinsics import Intrinsics
from floorscan.errors import FileFormatError

K = np.array([[300.0, 0.0, 159.5], [0.0, 301.0, 119.5], [0.0, 0.0, 1.0]])
D = np.array([-0.2, 0.05, 0.001, -0.002, 0.0])


def write_opencv(path, k=K, d=D):
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("camera_matrix", np.asarray(k, float))
    fs.write("distortion_coefficients", np.asarray(d, float))
    fs.write("image_width", 320)
    fs.write("image_height", 240)
    fs.release()
    return path


def ros_yaml(path, fx=300.0, d=(-0.2, 0.05, 0.001, -0.002, 0.0)):
    path.write_text(
        "image_width: 320\nimage_height: 240\ndistortion_model: plumb_bob\n"
        f"camera_matrix:\n  rows: 3\n  cols: 3\n  data: [{fx}, 0, 159.5, 0, 301, 119.5, 0, 0, 1]\n"
        f"distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: {list(d)}\n"
    )
    return path


def test_opencv_and_ros_files_give_what_was_written(tmp_path):
    for k in (
        Intrinsics.load(write_opencv(tmp_path / "k.yml")),
        Intrinsics.load(ros_yaml(tmp_path / "k.yaml")),
    ):
        assert k.image_size == (320, 240)
        assert np.allclose(k.params[:4], [300.0, 301.0, 159.5, 119.5])


@pytest.mark.parametrize(
    "k,d",
    [
        (K * [[1e-323, 1, 1], [1, 1e-323, 1], [1, 1, 1]], D),  # a denormal focal length
        (K * [[1e7, 1, 1], [1, 1, 1], [1, 1, 1]], D),
        (K, D * [1e308, 1, 1, 1, 1]),
        (K, [np.nan, 0, 0, 0, 0]),
    ],
)
def test_values_no_camera_has_are_refused(tmp_path, k, d):
    with pytest.raises(FileFormatError, match="k.yml"):
        Intrinsics.load(write_opencv(tmp_path / "k.yml", k, d))


def test_a_damaged_opencv_file_is_one_error(tmp_path):
    good = write_opencv(tmp_path / "k.yml").read_text()
    # the matrix's data cut short: OpenCV's parser asserts on the node
    bad = tmp_path / "bad.yml"
    bad.write_text(good[: good.index("data") + 12])
    with pytest.raises(FileFormatError, match="bad.yml") as e:
        Intrinsics.load(bad)
    assert "\n" not in str(e.value)
    ros = ros_yaml(tmp_path / "r.yaml", fx=1e-320)
    with pytest.raises(FileFormatError, match="r.yaml"):
        Intrinsics.load(ros)
