"""Frames and odometry arriving on topics, as the :class:`~floorscan.pipeline.sources.FrameSource`
that :func:`floorscan.pipeline.mapper.run` drives: the node runs the very loop ``floorscan run`` runs.

Images wait in a one-slot mailbox: a frame that arrives while the previous one still waits
replaces it (counted in :attr:`LiveSource.dropped`), so the node never falls behind the camera.
Decoding happens in the frame loop (its time is the pipeline's decode time).
"""

from __future__ import annotations

import bisect
import math
import sys
import threading
import time
from collections import deque
from typing import Callable, Deque, Iterator, Optional, Tuple

from ..errors import FloorscanError
from ..formats.trajectory import Pose2
from ..pipeline.sources import Frame, FrameSource

WAIT_S = 0.05
ODOM_HISTORY = 2000
"""Odometry messages kept (20 s at 100 Hz): the bound on the node's pose memory."""


def log(msg: str) -> None:
    print(f"floorscan node: {msg}", file=sys.stderr, flush=True)


class LiveOdometry:
    """The recent ``nav_msgs/Odometry`` poses; :meth:`pose_at` interpolates between them and
    holds the last pose up to ``timeout_s`` past it, never longer (then the frame is skipped)."""

    def __init__(self, timeout_s: float) -> None:
        self.timeout_s = float(timeout_s)
        self._lock = threading.Lock()
        self._t: Deque[float] = deque(maxlen=ODOM_HISTORY)
        self._p: Deque[Tuple[float, float, float]] = deque(maxlen=ODOM_HISTORY)
        self.received = 0
        self.rejected = 0
        self.stale = False

    def add(self, t: float, x: float, y: float, yaw: float) -> None:
        if not all(math.isfinite(v) for v in (t, x, y, yaw)):
            self.rejected += 1
            return
        with self._lock:
            if self._t and t <= self._t[-1]:
                self.rejected += 1  # out of order or repeated stamp
                return
            self._t.append(t)
            self._p.append((x, y, yaw))
            self.received += 1

    def pose_at(self, t: float) -> Optional[Pose2]:
        with self._lock:
            if not self._t:
                return self._note_stale(None, "no odometry received yet")
            ts = list(self._t)
            if t > ts[-1]:
                if t - ts[-1] > self.timeout_s:
                    return self._note_stale(
                        None, f"odometry stopped: last pose {t - ts[-1]:.2f} s before the frame"
                    )
                return self._note_stale(Pose2(*self._p[-1]), None)
            if t < ts[0]:
                return None
            i = bisect.bisect_right(ts, t) - 1
            if i >= len(ts) - 1:
                return self._note_stale(Pose2(*self._p[-1]), None)
            (x0, y0, a0), (x1, y1, a1) = self._p[i], self._p[i + 1]
            a = (t - ts[i]) / (ts[i + 1] - ts[i])
            dyaw = math.remainder(a1 - a0, 2 * math.pi)
            pose = Pose2(
                x0 + a * (x1 - x0), y0 + a * (y1 - y0), math.remainder(a0 + a * dyaw, 2 * math.pi)
            )
            return self._note_stale(pose, None)

    def _note_stale(self, pose: Optional[Pose2], why: Optional[str]) -> Optional[Pose2]:
        if why is not None and not self.stale:
            log(f"{why}; frames are skipped until it resumes")
        elif why is None and self.stale:
            log("odometry resumed")
        self.stale = why is not None
        return pose


class LiveSource(FrameSource):
    """Frames from a subscription. ``decode(bytes) -> (stamp [s], image)`` raises a
    FloorscanError for a message it cannot read (the frame is skipped and counted)."""

    live = True

    def __init__(
        self,
        decode: Callable[[bytes], tuple],
        *,
        odometry: Optional[LiveOdometry],
        health: Callable[[], Optional[str]] = lambda: None,
        max_frames: Optional[int] = None,
        expected_shape: Optional[Tuple[int, int]] = None,
    ) -> None:
        self._decode = decode
        self._shape = expected_shape
        self._said: set = set()
        self.odometry = odometry
        self._health = health
        self._max_frames = max_frames
        self._cond = threading.Condition()
        self._slot: Optional[Tuple[bytes, float]] = None
        self._closed = False
        self._stop = None
        self.received = 0
        self.dropped = 0
        self.current_receive_time: Optional[float] = None
        self._health_said: Optional[str] = None

    def bind_stop(self, stop) -> None:
        self._stop = stop

    def push(self, data: bytes, received: float) -> None:
        """Transport callback: one image message arrived at ``received`` (perf_counter)."""
        with self._cond:
            self.received += 1
            if self._slot is not None:
                self.dropped += 1
            self._slot = (data, received)
            self._cond.notify()

    def _next(self) -> Optional[Tuple[bytes, float]]:
        with self._cond:
            while self._slot is None:
                if self._closed or (self._stop is not None and self._stop.requested):
                    return None
                self._cond.wait(WAIT_S)
                self._check_health()
            item, self._slot = self._slot, None
            return item

    def _check_health(self) -> None:
        h = self._health()
        if h != self._health_said:
            log(h if h is not None else "middleware is back")
            self._health_said = h

    def __iter__(self) -> Iterator[Frame]:
        index = 0
        while self._max_frames is None or index < self._max_frames:
            item = self._next()
            if item is None:
                return
            data, received = item
            self.current_receive_time = received
            try:
                t, image = self._decode(data)
            except FloorscanError as e:
                self._say_once(type(e).__name__ + str(e)[:40], f"frame {index} skipped: {e}")
                yield Frame(index, time.time(), None, str(e))
            else:
                if self._shape is not None and image.shape[:2] != self._shape:
                    h, w = self._shape
                    self._say_once(
                        f"size {image.shape[:2]}",
                        f"frames of {image.shape[1]}x{image.shape[0]} are skipped: the ground table is for {w}x{h}",
                    )
                yield Frame(index, t, image)
            index += 1

    def _say_once(self, key: str, msg: str) -> None:
        if key not in self._said and len(self._said) < 100:
            self._said.add(key)
            log(msg + " (logged once)")

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify_all()
