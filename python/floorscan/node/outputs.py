"""What the node sends out, per frame and at a fixed rate, around the files ``floorscan run``
writes (the wrapped :class:`~floorscan.pipeline.outputs.RunOutputs`, so the map and everything else
is saved on shutdown exactly as a run saves it):

- every scan as ``sensor_msgs/LaserScan`` (REP 117) in the camera ground frame, binned as the
  run's bag binning (``outputs.laser_angle_increment_rad``);
- the global and the local map as ``nav_msgs/OccupancyGrid`` every ``node.map_period_s``;
- the static transform base_frame -> scan_frame (latched) at start;
- every frame, ``map_frame -> odom_frame`` on ``tf_topic``: the scan matcher's correction
  (REP 105's ``map -> odom``, as slam_toolbox publishes it; identity with ``[slam]`` off), so
  a planner sees maps that stay put while odometry drifts (none when the two frames are one);
- optionally (``node.overlay_topic``) each frame with its boundary points drawn, rgb8.

Latency is image received (transport callback) -> scan published, decode included.
"""

from __future__ import annotations

import time
from typing import Dict, List, Optional

import numpy as np

from ..ranging.overlay import draw_scan_overlay
from . import messages as M
from .live_source import log

MAX_LATENCIES = 1 << 20
"""Latencies kept for the percentiles (about 29 h at 10 Hz); later ones are counted only."""
LOG_PERIOD_S = 10.0


class NodeOutputs:
    def __init__(self, inner, transport, codec, node_cfg, source, robot_from_camera) -> None:
        self.inner = inner
        self.out = inner.out
        self.finishing = False
        self.cfg = node_cfg
        self.codec = codec
        self.source = source
        n = node_cfg
        self.scan_pub = transport.advertise(n.scan_topic, M.LASER_SCAN)
        self.map_pub = transport.advertise(n.map_topic, M.OCCUPANCY_GRID, latched=True)
        self.local_pub = transport.advertise(n.local_map_topic, M.OCCUPANCY_GRID, latched=True)
        self.overlay_pub = (
            transport.advertise(n.overlay_topic, M.IMAGE) if n.overlay_topic else None
        )
        tf_pub = transport.advertise(n.tf_static_topic, M.TF_MESSAGE, latched=True)
        tf_pub.publish(codec.transform(time.time(), n.base_frame, n.scan_frame, robot_from_camera))
        self.tf_pub = (
            transport.advertise(n.tf_topic, M.TF_MESSAGE)
            if n.tf_topic and n.map_frame != n.odom_frame
            else None
        )
        self.map_listeners: List = []
        """Called as ``f(mapper, t)`` after each map publication (the live view)."""
        self.latencies_s: List[float] = []
        self.scans_published = 0
        self.publish_errors = 0
        self.maps_published = 0
        self._next_map = time.perf_counter() + n.map_period_s
        self._next_log = time.perf_counter() + LOG_PERIOD_S

    def on_frame(self, frame, scan, pose, mapper) -> None:
        lo, hi, inc = self.inner.laser_angles(scan)
        laser = scan.to_laser_scan(angle_min=lo, angle_max=hi, angle_increment=inc)
        self._publish(
            self.scan_pub, self.codec.laser_scan(scan.timestamp, laser, self.cfg.scan_frame)
        )
        now = time.perf_counter()
        received = self.source.current_receive_time
        if self.overlay_pub is not None:  # after the latency: the overlay is a side output
            rgb = draw_scan_overlay(frame.image, scan)
            self._publish(self.overlay_pub, self.codec.rgb_image(scan.timestamp, rgb, "camera"))
        if received is not None and len(self.latencies_s) < MAX_LATENCIES:
            self.latencies_s.append(now - received)
        self.scans_published += 1
        self.inner.on_frame(frame, scan, pose, mapper)
        if self.tf_pub is not None:
            correction = mapper.slam.map_from_odom if mapper.slam is not None else (0.0, 0.0, 0.0)
            self._publish(
                self.tf_pub,
                self.codec.transform(
                    scan.timestamp, self.cfg.map_frame, self.cfg.odom_frame, correction
                ),
            )
        if now >= self._next_map:
            self.publish_maps(mapper, scan.timestamp)
            self._next_map = now + self.cfg.map_period_s
        if now >= self._next_log:
            log(self.status_line())
            self._next_log = now + LOG_PERIOD_S

    def publish_maps(self, mapper, t: float) -> None:
        f = self.cfg.map_frame
        for pub, grid in ((self.map_pub, mapper.global_map), (self.local_pub, mapper.local_map)):
            data, res, origin = grid.to_occupancy_grid()
            self._publish(pub, self.codec.occupancy_grid(t, data, res, origin, f))
        self.maps_published += 1
        for listener in self.map_listeners:
            listener(mapper, t)

    def _publish(self, pub, data: bytes) -> None:
        """A middleware that fails to send must not stop the mapping (the map is saved at the
        end either way): the failure is counted and logged once."""
        try:
            pub.publish(data)
        except Exception as e:  # rospy / zenoh raise their own types
            self.publish_errors += 1
            if self.publish_errors == 1:
                log(f"publishing failed: {e} (logged once; counted in summary.json)")

    def latency_ms(self) -> Dict[str, Optional[float]]:
        if not self.latencies_s:
            return {"count": 0, "p50": None, "p90": None, "p99": None, "max": None}
        a = 1e3 * np.asarray(self.latencies_s)
        p50, p90, p99 = np.percentile(a, [50, 90, 99])
        return {
            "count": int(a.size),
            "p50": round(float(p50), 3),
            "p90": round(float(p90), 3),
            "p99": round(float(p99), 3),
            "max": round(float(a.max()), 3),
        }

    def status_line(self) -> str:
        lat = self.latency_ms()
        s = self.source
        text = f"{s.received} images received, {self.scans_published} scans published, {s.dropped} dropped"
        if lat["count"]:
            text += f", latency p50 {lat['p50']:.2f} ms p99 {lat['p99']:.2f} ms"
        return text

    def finish(self, mapper, stats) -> None:
        self.finishing = True
        try:
            if mapper.frames:
                self.publish_maps(mapper, float(self.inner.extra_summary.get("last_timestamp", 0)))
        except Exception as e:  # the middleware may be gone: the files are what must survive
            log(f"final map not published: {e}")
        self.inner.extra_summary["node"] = {
            "transport": self.cfg.transport,
            "images_received": self.source.received,
            "dropped_frames": self.source.dropped,
            "scans_published": self.scans_published,
            "maps_published": self.maps_published,
            "publish_errors": self.publish_errors,
            "latency_ms": self.latency_ms(),
        }
        log(self.status_line())
        self.inner.finish(mapper, stats)

    def discard(self) -> None:
        self.inner.discard()
