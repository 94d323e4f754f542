"""floorscan live on a robot: ``floorscan node`` and its Python API :func:`run_node`.

The node subscribes to a camera and an odometry topic, runs every frame through the same
:class:`~floorscan.pipeline.mapper.Mapper` and frame loop as ``floorscan run`` (:func:`floorscan.pipeline.mapper.run`,
with its signal handling: SIGINT, SIGTERM or SIGHUP stop it and every output is saved), and
publishes scans and maps (:mod:`.outputs`). The middleware is a :class:`.transport.Transport`:
ROS 1 through rospy (:mod:`.ros1`) or ROS 2 through rmw_zenoh's protocol (:mod:`.zenoh`).
See docs/node.md.
"""

from __future__ import annotations

from typing import Optional, Tuple

from ..pipeline.config import Config
from ..pipeline.config_check import check_config
from ..pipeline.mapper import Mapper, RunStats, run
from ..pipeline.outputs import RunOutputs
from ..ranging.ground_table import GroundTable
from . import messages as M
from .live_source import LiveOdometry, LiveSource, log
from .live_view import FoxgloveView
from .outputs import NodeOutputs
from .ros1 import Ros1Transport
from .transport import Transport
from .zenoh import ZenohTransport

__all__ = ["run_node", "NodeRun", "Transport", "open_transport"]


class NodeRun:
    """A node wired to a transport, not yet running: :meth:`run` blocks until a stop signal
    (or ``max_frames`` frames), then saves every output into ``output``."""

    def __init__(
        self,
        table: GroundTable,
        cfg: Config,
        output,
        *,
        transport: Optional[Transport] = None,
        robot_from_camera: Tuple[float, float, float] = (0.0, 0.0, 0.0),
        max_frames: Optional[int] = None,
    ) -> None:
        check_config(cfg)
        n = cfg.node
        self.transport = transport if transport is not None else open_transport(n)
        self.codec = M.Codec(self.transport.ros_version)
        self.mapper = Mapper(table, cfg, robot_from_camera=robot_from_camera)
        image_type = M.COMPRESSED_IMAGE if n.compressed else M.IMAGE
        self.bad_odometry = 0
        use_tf = n.odom_source == "tf"
        self.odometry = LiveOdometry(n.odom_timeout_s) if (use_tf or n.odom_topic) else None
        self.source = LiveSource(
            lambda data: self.codec.decode_image(data, image_type),
            odometry=self.odometry,
            health=self.transport.health,
            max_frames=max_frames,
            expected_shape=(table.image_height, table.image_width),
        )
        self.outputs = NodeOutputs(
            RunOutputs(output, cfg),
            self.transport,
            self.codec,
            n,
            self.source,
            self.mapper.robot_from_camera,
        )
        if n.foxglove_port:
            self.outputs = FoxgloveView(self.outputs, n, self.mapper.robot_from_camera)
        self.transport.subscribe(n.image_topic, image_type, self.source.push)
        if use_tf:
            self.transport.subscribe(n.tf_topic, M.TF_MESSAGE, self._on_tf)
        elif self.odometry is not None:
            self.transport.subscribe(n.odom_topic, M.ODOMETRY, self._on_odometry)

    def _on_odometry(self, data: bytes, _received: float) -> None:
        try:
            self.odometry.add(*self.codec.decode_odometry(data))
        except Exception as e:  # a damaged message: counted, logged once
            self.bad_odometry += 1
            if self.bad_odometry == 1:
                log(f"odometry message skipped: {e} (logged once)")

    def _on_tf(self, data: bytes, _received: float) -> None:
        n = self.mapper.cfg.node
        try:
            poses = self.codec.decode_tf(data, n.odom_frame, n.base_frame)
        except Exception as e:  # a damaged message: counted, logged once
            self.bad_odometry += 1
            if self.bad_odometry == 1:
                log(f"transform message skipped: {e} (logged once)")
            return
        for pose in poses:
            self.odometry.add(*pose)

    def run(self) -> RunStats:
        n = self.mapper.cfg.node
        log(
            f"{type(self.transport).__name__}: {n.image_topic} + "
            f"{n.tf_topic + ' (tf)' if n.odom_source == 'tf' else n.odom_topic or '(no odometry)'} -> "
            f"{n.scan_topic}, {n.map_topic}, {n.local_map_topic}"
        )
        try:
            return run(self.source, self.mapper, self.outputs)
        finally:
            self.transport.close()


def run_node(table: GroundTable, cfg: Config, output, **kw) -> RunStats:
    """Runs the node until stopped; see :class:`NodeRun` for the arguments."""
    return NodeRun(table, cfg, output, **kw).run()


def open_transport(node_cfg) -> Transport:
    """The transport the ``[node]`` options name."""
    if node_cfg.transport == "ros1":
        return Ros1Transport(node_cfg.node_name)
    return ZenohTransport(
        node_cfg.node_name,
        domain_id=node_cfg.domain_id,
        mode=node_cfg.zenoh_mode,
        connect=node_cfg.zenoh_connect or None,
        listen=node_cfg.zenoh_listen or None,
    )
