"""The names rmw_zenoh (ROS 2's Zenoh middleware) gives to topics, graph entities and message
metadata, as its design document (ros2/rmw_zenoh docs/design.md, Jazzy and later) specifies:

- topic data key expression ``<domain_id>/<topic without the leading />/<DDS type name>/<type hash>``,
  e.g. ``0/chatter/std_msgs::msg::dds_::String_/RIHS01_df66...``;
- liveliness tokens of the graph cache
  ``@ros2_lv/<domain_id>/<zenoh id>/<node id>/<entity id>/<NN|MP|MS|SS|SC>/<enclave>/<namespace>/<node name>``
  followed, for publishers and subscriptions, by ``/<mangled topic>/<type>/<type hash>/<qos>``;
  names are mangled by replacing every ``/`` with ``%`` (an empty enclave or the root
  namespace is ``%``);
- the QoS field ``<reliability>:<durability>:<history>,<depth>:<deadline s>,<ns>:<lifespan s>,<ns>:<liveliness>,<lease s>,<ns>``
  with every component left empty when it is rmw_zenoh's default;
- the attachment of every sample: sequence number (int64), source timestamp [ns] (int64), and
  the publisher's 16-byte gid, in Zenoh's serialisation (little-endian integers, the gid as a
  sequence: its LEB128 length 16, then the bytes), 33 bytes in all.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Optional, Tuple

ADMIN_SPACE = "@ros2_lv"
GID_SIZE = 16
ATTACHMENT_SIZE = 8 + 8 + 1 + GID_SIZE

# rmw/types.h enumerations
RELIABLE, BEST_EFFORT = 1, 2
TRANSIENT_LOCAL, VOLATILE = 1, 2
KEEP_LAST, KEEP_ALL = 1, 2
DEFAULT_DEPTH = 42
"""rmw_zenoh's depth for a KEEP_LAST depth of 0 (docs/design.md, Quality of Service): left out."""


@dataclass(frozen=True)
class Qos:
    reliability: int = RELIABLE
    durability: int = VOLATILE
    history: int = KEEP_LAST
    depth: int = 10

    def keyexpr(self) -> str:
        """The QoS field of a liveliness token (defaults left empty; infinite deadline,
        lifespan and lease, automatic liveliness)."""
        rel = "" if self.reliability == RELIABLE else str(self.reliability)
        dur = "" if self.durability == VOLATILE else str(self.durability)
        hist = "" if self.history == KEEP_LAST else str(self.history)
        depth = "" if self.depth == DEFAULT_DEPTH else str(self.depth)
        return f"{rel}:{dur}:{hist},{depth}:,:,:,,"


SENSOR_QOS = Qos(depth=10)
LATCHED_QOS = Qos(durability=TRANSIENT_LOCAL, depth=1)


def dds_type_name(msgtype: str) -> str:
    """``sensor_msgs/msg/LaserScan`` -> ``sensor_msgs::msg::dds_::LaserScan_``."""
    pkg, kind, name = msgtype.split("/")
    return f"{pkg}::{kind}::dds_::{name}_"


def mangle(name: str) -> str:
    """Every ``/`` as ``%``; the empty name is ``%``."""
    return name.replace("/", "%") if name else "%"


def topic_keyexpr(domain_id: int, topic: str, msgtype: str, type_hash: str) -> str:
    """Key expression of a topic's samples."""
    return f"{domain_id}/{topic.strip('/')}/{dds_type_name(msgtype)}/{type_hash}"


def node_token(
    domain_id: int, zid: str, node_id: int, node_name: str, namespace: str = "/", enclave: str = ""
) -> str:
    ns = "%" if namespace in ("", "/") else mangle(namespace)
    return (
        f"{ADMIN_SPACE}/{domain_id}/{zid}/{node_id}/{node_id}/NN/{mangle(enclave)}/{ns}/{node_name}"
    )


def endpoint_token(
    domain_id: int,
    zid: str,
    node_id: int,
    entity_id: int,
    kind: str,
    node_name: str,
    topic: str,
    msgtype: str,
    type_hash: str,
    qos: Qos,
    namespace: str = "/",
    enclave: str = "",
) -> str:
    """Liveliness token of a publisher (``kind`` "MP") or a subscription ("MS")."""
    if kind not in ("MP", "MS"):
        raise ValueError(f"kind must be MP or MS, got {kind!r}")
    ns = "%" if namespace in ("", "/") else mangle(namespace)
    fq = topic if topic.startswith("/") else "/" + topic
    return (
        f"{ADMIN_SPACE}/{domain_id}/{zid}/{node_id}/{entity_id}/{kind}/{mangle(enclave)}/{ns}/"
        f"{node_name}/{mangle(fq)}/{dds_type_name(msgtype)}/{type_hash}/{qos.keyexpr()}"
    )


def attachment(sequence_number: int, source_timestamp_ns: int, gid: bytes) -> bytes:
    if len(gid) != GID_SIZE:
        raise ValueError(f"gid must be {GID_SIZE} bytes, got {len(gid)}")
    return struct.pack("<qqB", sequence_number, source_timestamp_ns, GID_SIZE) + bytes(gid)


def parse_attachment(data: Optional[bytes]) -> Optional[Tuple[int, int, bytes]]:
    """(sequence number, source timestamp [ns], gid), or None for a malformed attachment."""
    if data is None or len(data) != ATTACHMENT_SIZE or data[16] != GID_SIZE:
        return None
    seq, ts = struct.unpack_from("<qq", data)
    return seq, ts, bytes(data[17:])
