"""A live view of the node in Foxglove: a Foxglove WebSocket server (``foxglove-sdk``) that
streams the camera image with the boundary points circled, the scan, both maps and the robot's
transforms, so a user opens Foxglove (``ws://HOST:PORT``) and watches the robot.

Channels (Foxglove schemas, protobuf): ``/camera/image`` (RawImage, mono8),
``/camera/boundary`` (ImageAnnotations: the boundary points), ``/scan`` (LaserScan in the scan
frame), ``/map`` and ``/local_map`` (Grid, one int8 field ``occupancy``: -1 unknown, 0..100,
row 0 at the map's bottom, as nav_msgs/OccupancyGrid), ``/tf`` (FrameTransforms: map frame ->
base frame from odometry, base frame -> scan frame from the rig). Enabled with
``node.foxglove_port`` (0: off) or ``floorscan node --foxglove PORT``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import OptionError
from ..ranging.scan import ColumnStatus


def _import_foxglove():
    try:
        import foxglove
        import foxglove.channels as ch
        import foxglove.messages as fm
    except ImportError:
        raise OptionError(
            "the live view needs foxglove-sdk: pip install 'floorscan[live]'"
        ) from None
    return foxglove, ch, fm


class FoxgloveView:
    """Wraps the node's outputs (see :class:`~floorscan.node.outputs.NodeOutputs`): each frame
    and each map publication is also sent to Foxglove."""

    def __init__(self, inner, node_cfg, robot_from_camera, *, host: str = "127.0.0.1") -> None:
        fg, ch, fm = _import_foxglove()
        self.inner, self.out, self.fm = inner, inner.out, fm
        self.cfg = node_cfg
        self.finishing = False
        self.robot_from_camera = robot_from_camera
        self.context = fg.Context()
        self.server = fg.start_server(
            name="floorscan", host=host, port=node_cfg.foxglove_port, context=self.context
        )
        self.port = self.server.port
        c = self.context
        self.image = ch.RawImageChannel("/camera/image", context=c)
        self.boundary = ch.ImageAnnotationsChannel("/camera/boundary", context=c)
        self.scan = ch.LaserScanChannel("/scan", context=c)
        self.global_map = ch.GridChannel("/map", context=c)
        self.local_map = ch.GridChannel("/local_map", context=c)
        self.tf = ch.FrameTransformsChannel("/tf", context=c)
        inner.map_listeners.append(self._on_maps)

    # --- helpers ----------------------------------------------------------------------
    def _time(self, t: float):
        sec = int(math.floor(t))
        return self.fm.Timestamp(sec=sec, nsec=int(round((t - sec) * 1e9)) % 1_000_000_000)

    def _pose(self, x: float, y: float, yaw: float):
        fm = self.fm
        return fm.Pose(
            position=fm.Vector3(x=float(x), y=float(y), z=0.0),
            orientation=fm.Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)),
        )

    def _transform(self, t, parent: str, child: str, x, y, yaw):
        fm = self.fm
        return fm.FrameTransform(
            timestamp=self._time(t),
            parent_frame_id=parent,
            child_frame_id=child,
            translation=fm.Vector3(x=float(x), y=float(y), z=0.0),
            rotation=fm.Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)),
        )

    # --- per frame ----------------------------------------------------------------------
    def on_frame(self, frame, scan, pose, mapper) -> None:
        self.inner.on_frame(frame, scan, pose, mapper)
        fm, t, n = self.fm, scan.timestamp, self.cfg
        grey = np.ascontiguousarray(frame.image)
        if grey.dtype != np.uint8:
            grey = (grey >> 8).astype(np.uint8)  # mono16 shown by its high byte
        h, w = grey.shape
        ts = self._time(t)
        self.image.log(
            fm.RawImage(
                timestamp=ts,
                frame_id="camera",
                width=w,
                height=h,
                encoding="mono8",
                step=w,
                data=grey.tobytes(),
            )
        )
        ok = scan.status_codes == ColumnStatus.BOUNDARY
        points = [
            fm.Point2(x=float(c) + 0.5, y=float(r) + 0.5)
            for c, r in zip(scan.columns[ok], scan.rows[ok])
        ]
        self.boundary.log(
            fm.ImageAnnotations(
                points=[
                    fm.PointsAnnotation(
                        timestamp=ts,
                        type=fm.PointsAnnotationType.Points,
                        points=points,
                        outline_color=fm.Color(r=1.0, g=0.2, b=0.2, a=1.0),
                        thickness=6.0,
                    )
                ]
            )
        )
        lo, hi, inc = self.inner.inner.laser_angles(scan)
        laser = scan.to_laser_scan(angle_min=lo, angle_max=hi, angle_increment=inc)
        self.scan.log(
            fm.LaserScan(
                timestamp=ts,
                frame_id=n.scan_frame,
                pose=self._pose(0, 0, 0),
                start_angle=float(laser["angle_min"]),
                end_angle=float(laser["angle_max"]),
                ranges=[float(r) for r in laser["ranges"]],
                intensities=[],
            )
        )
        tfs = [self._transform(t, n.base_frame, n.scan_frame, *self.robot_from_camera)]
        if pose is not None:
            tfs.append(self._transform(t, n.map_frame, n.base_frame, *pose))
        self.tf.log(fm.FrameTransforms(transforms=tfs))

    def _on_maps(self, mapper, t: float) -> None:
        for channel, grid in (
            (self.global_map, mapper.global_map),
            (self.local_map, mapper.local_map),
        ):
            channel.log(self.grid(grid, t))

    def grid(self, grid, t: float):
        fm = self.fm
        data, res, origin = grid.to_occupancy_grid()
        h, w = data.shape
        return fm.Grid(
            timestamp=self._time(t),
            frame_id=self.cfg.map_frame,
            pose=self._pose(*origin),
            column_count=w,
            cell_size=fm.Vector2(x=res, y=res),
            row_stride=w,
            cell_stride=1,
            fields=[
                fm.PackedElementField(
                    name="occupancy", offset=0, type=fm.PackedElementFieldNumericType.Int8
                )
            ],
            data=np.ascontiguousarray(data, dtype=np.int8).tobytes(),
        )

    def finish(self, mapper, stats) -> None:
        self.finishing = True
        try:
            self.inner.finish(mapper, stats)
        finally:
            self.server.stop()

    def discard(self) -> None:
        self.server.stop()
        self.inner.discard()
