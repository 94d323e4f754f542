"""Range checks of the ``[node]`` options (the table is
:class:`floorscan.pipeline.config.NodeConfig`; types are checked when the file is read). Here, not in
:mod:`floorscan.node`, so that checking a configuration does not import the node."""

from __future__ import annotations

import math
import re

from ..errors import OptionError

TRANSPORTS = ("ros1", "zenoh")
ODOM_SOURCES = ("odometry", "tf")
ZENOH_MODES = ("peer", "client")
MAX_DOMAIN_ID = 232
"""The largest ROS 2 domain id (ROS 2 documentation, "The ROS_DOMAIN_ID")."""

_NAME = re.compile(r"^/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$")
_FRAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_./-]*$")


def _bad(key: str, why: str, value) -> OptionError:
    return OptionError(f"invalid option `node.{key}`: {why}, got {value!r}")


def check_node(n) -> None:
    """Raises OptionError naming the ``[node]`` key that is out of range."""
    if n.transport not in TRANSPORTS:
        raise _bad("transport", f"expected one of {', '.join(TRANSPORTS)}", n.transport)
    if n.odom_source not in ODOM_SOURCES:
        raise _bad("odom_source", f"expected one of {', '.join(ODOM_SOURCES)}", n.odom_source)
    if n.zenoh_mode not in ZENOH_MODES:
        raise _bad("zenoh_mode", f"expected one of {', '.join(ZENOH_MODES)}", n.zenoh_mode)
    topics = ["image_topic", "scan_topic", "map_topic", "local_map_topic", "tf_static_topic"]
    topics += [k for k in ("odom_topic", "overlay_topic", "tf_topic") if getattr(n, k)]
    for key in topics:
        v = getattr(n, key)
        if not _NAME.match(v):
            raise _bad(key, "must be a ROS name (letters, digits, _ and /)", v)
    for key in ("base_frame", "scan_frame", "map_frame", "odom_frame"):
        v = getattr(n, key)
        if not _FRAME.match(v):
            raise _bad(key, "must be a frame id (letters, digits, _ . / -)", v)
    if not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", n.node_name):
        raise _bad("node_name", "must be a ROS node name (letters, digits, _)", n.node_name)
    if not (math.isfinite(n.map_period_s) and 0.01 <= n.map_period_s <= 3600):
        raise _bad("map_period_s", "must be in [0.01, 3600] s", n.map_period_s)
    if not (math.isfinite(n.odom_timeout_s) and n.odom_timeout_s > 0):
        raise _bad("odom_timeout_s", "must be finite and > 0", n.odom_timeout_s)
    if not 0 <= n.foxglove_port <= 65535:
        raise _bad("foxglove_port", "must be in 0..=65535 (0: no live view)", n.foxglove_port)
    if not 0 <= n.domain_id <= MAX_DOMAIN_ID:
        raise _bad("domain_id", f"must be in 0..={MAX_DOMAIN_ID}", n.domain_id)
