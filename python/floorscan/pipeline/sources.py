"""Where frames come from: a dataset folder, a video file, a live camera, or a ROS bag.

Each source yields :class:`Frame` s in time order; a frame that cannot be read is yielded with
``image=None`` and the reason, so the pipeline can count it (or stop, with ``--strict``).
Odometry, when the source has it, is a :class:`~floorscan.formats.trajectory.Trajectory`.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Optional

import numpy as np

from .._atomic import PathLike
from ..errors import DatasetError, FloorscanError, ImageError
from ..formats.dataset import read_images_txt
from ..formats.image_io import as_grey, check_image_size, read_grey
from ..formats.native_messages import native_messages
from ..formats.read_ahead import read_grey_ahead
from ..formats.rig import Rig, read_rig
from ..formats.rosbag import iter_bag_images, read_bag_odometry
from ..formats.trajectory import Trajectory, read_tum


@dataclass
class Frame:
    index: int
    timestamp: float
    image: Optional[np.ndarray]
    """(H, W) uint8/uint16 grey, or None when the frame could not be read."""
    error: Optional[str] = None


class FrameSource:
    """Base class: iterate for frames. ``live`` sources drop frames rather than fall behind."""

    live: bool = False
    odometry: Optional[Trajectory] = None
    rig: Optional[Rig] = None
    dropped: int = 0

    def __iter__(self) -> Iterator[Frame]:  # pragma: no cover - interface
        raise NotImplementedError

    def __len__(self) -> int:
        return 0

    def bind_stop(self, stop) -> None:
        """The run's :class:`~floorscan._signals.StopRequest`: a source that waits for frames
        (a live subscription) ends its iteration once a stop is requested."""

    def close(self) -> None:
        pass


class DatasetSource(FrameSource):
    """A dataset folder in the documented format (docs/dataset-format.md)."""

    def __init__(self, folder: PathLike) -> None:
        self.folder = Path(folder)
        self.entries = read_images_txt(self.folder)
        odo = self.folder / "odometry.txt"
        self.odometry = read_tum(odo) if odo.is_file() else None
        gt = self.folder / "groundtruth.txt"
        self.groundtruth = read_tum(gt) if gt.is_file() else None
        rig = self.folder / "rig.toml"
        self.rig = read_rig(rig) if rig.is_file() else None
        self._images: Optional[Iterator] = None

    def close(self) -> None:
        """Stops the read-ahead of an iteration that did not reach the end."""
        if self._images is not None:
            self._images.close()
            self._images = None

    def __len__(self) -> int:
        return len(self.entries)

    def __iter__(self) -> Iterator[Frame]:
        """Frames in order, decoded ahead of the frame loop: PNG files by Rust threads
        (:mod:`floorscan.formats.read_ahead`), other formats in their turn by Pillow."""
        self.close()
        self._images = images = read_grey_ahead([e.path for e in self.entries])
        try:
            for i, (e, image) in enumerate(zip(self.entries, images)):
                if isinstance(image, FloorscanError):
                    yield Frame(i, e.timestamp, None, str(image))
                else:
                    yield Frame(i, e.timestamp, image)
        finally:
            self.close()

    def _frames(self) -> Iterator[Frame]:
        """Frames in order, each decoded in its turn (no read-ahead)."""
        for i, e in enumerate(self.entries):
            try:
                yield Frame(i, e.timestamp, read_grey(e.path))
            except FloorscanError as err:
                yield Frame(i, e.timestamp, None, str(err))


class VideoSource(FrameSource):
    """A video file (anything OpenCV reads); frame times from the container, offset by
    ``start_time`` [s] so they can match an odometry file's clock."""

    def __init__(
        self, path: PathLike, *, odometry: Optional[PathLike] = None, start_time: float = 0.0
    ) -> None:
        import cv2

        self.path = Path(path)
        if not self.path.is_file():
            raise DatasetError(f"video not found: {self.path}")
        with native_messages() as said:
            self._cap = cv2.VideoCapture(str(self.path))
            opened = self._cap.isOpened()
        if not opened:
            why = f" ({said.first})" if said else ""
            raise DatasetError(f"cannot open video {self.path}{why}")
        w = int(self._cap.get(cv2.CAP_PROP_FRAME_WIDTH) or 0)
        h = int(self._cap.get(cv2.CAP_PROP_FRAME_HEIGHT) or 0)
        try:
            check_image_size(w, h, f"video {self.path}")  # before a frame is decoded
        except ImageError as e:
            self._cap.release()
            raise DatasetError(str(e)) from None
        self.odometry = read_tum(odometry) if odometry else None
        self.start_time = float(start_time)
        self._fps = self._cap.get(cv2.CAP_PROP_FPS) or 10.0
        self._count = int(self._cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0)

    def __len__(self) -> int:
        return max(self._count, 0)

    def __iter__(self) -> Iterator[Frame]:
        i = 0
        while True:
            with native_messages() as said:
                ok, img = self._cap.read()
            if not ok:
                break
            if said:
                # the decoder complained: the frame is damaged (decoded in part, or garbage),
                # skipped and counted as a damaged image file is
                yield Frame(i, self.start_time + i / self._fps, None, f"decoder: {said.first}")
                i += 1
                continue
            yield Frame(
                i,
                self.start_time + i / self._fps,
                as_grey(np.ascontiguousarray(img[..., ::-1]) if img.ndim == 3 else img),
            )
            i += 1
        self._cap.release()

    def close(self) -> None:
        self._cap.release()


class CameraSource(FrameSource):
    """A live camera (OpenCV device index). A background thread keeps only the newest frame; the
    consumer always gets the latest one and ``dropped`` counts the frames it never saw."""

    live = True

    def __init__(
        self, device: int, *, odometry: Optional[PathLike] = None, max_frames: Optional[int] = None
    ) -> None:
        import cv2

        self._cap = cv2.VideoCapture(int(device))
        if not self._cap.isOpened():
            raise DatasetError(f"cannot open camera device {device}")
        self.odometry = read_tum(odometry) if odometry else None
        self.max_frames = max_frames
        self._latest: Optional[np.ndarray] = None
        self._latest_t = 0.0
        self._grabbed = 0
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._grab, daemon=True)
        self._thread.start()

    def _grab(self) -> None:
        while not self._stop.is_set():
            ok, img = self._cap.read()
            if not ok:
                time.sleep(0.01)
                continue
            with self._lock:
                self._latest, self._latest_t = img, time.time()
                self._grabbed += 1

    def __iter__(self) -> Iterator[Frame]:
        i, seen = 0, 0
        while self.max_frames is None or i < self.max_frames:
            with self._lock:
                img, t, grabbed = self._latest, self._latest_t, self._grabbed
                self._latest = None
            if img is None:
                time.sleep(0.002)
                continue
            self.dropped += grabbed - seen - 1
            seen = grabbed
            yield Frame(
                i, t, as_grey(np.ascontiguousarray(img[..., ::-1]) if img.ndim == 3 else img)
            )
            i += 1

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=1.0)
        self._cap.release()


class BagSource(FrameSource):
    """A ROS 1 (``.bag``) or ROS 2 (folder) bag: images and odometry from named topics."""

    def __init__(
        self, path: PathLike, *, image_topic: str, odom_topic: Optional[str] = None
    ) -> None:
        self.path = Path(path)
        self.image_topic = image_topic
        self.odometry = read_bag_odometry(self.path, odom_topic=odom_topic) if odom_topic else None

    def __iter__(self) -> Iterator[Frame]:
        images = iter_bag_images(self.path, image_topic=self.image_topic)
        for i, (t, img, error) in enumerate(images):
            yield Frame(i, t, img, error)
