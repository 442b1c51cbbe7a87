"""What a graph query says about one publisher or subscription (rclpy.topic_endpoint_info).

Node.get_publishers_info_by_topic and get_subscriptions_info_by_topic return these, built from
the graph's records (zros.graph.Entity), in the shape rclpy's tools read: node, type, type
hash, endpoint kind, a unique id, and the QoS the endpoint announced.
"""
from __future__ import annotations

import enum
from typing import Any

from zros.qos import DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSProfile, ReliabilityPolicy
from zros.type_hash import TypeHash

__all__ = ['TopicEndpointTypeEnum', 'TopicEndpointInfo']


class TopicEndpointTypeEnum(enum.IntEnum):
    """The kind of endpoint (rmw's values)."""
    INVALID = 0
    PUBLISHER = 1
    SUBSCRIPTION = 2


#: What an endpoint info holds before the graph says: every policy UNKNOWN (rmw's unknown profile).
_UNKNOWN_QOS = QoSProfile(history=HistoryPolicy.UNKNOWN, depth=0, reliability=ReliabilityPolicy.UNKNOWN,
                          durability=DurabilityPolicy.UNKNOWN, liveliness=LivelinessPolicy.UNKNOWN)


class TopicEndpointInfo:
    """One endpoint of a topic; constructed by the node's graph queries, fields by keyword.

    :param node_name: The name of the endpoint's node.
    :param node_namespace: That node's namespace.
    :param topic_type: E.g. ``'std_msgs/msg/String'``.
    :param topic_type_hash: A TypeHash (INVALID where the graph has no RIHS hash, see
        zros.type_hash), or its ``version``/``value`` as a dict.
    :param endpoint_type: A TopicEndpointTypeEnum (or its int).
    :param endpoint_gid: The endpoint's unique id, as a list of byte values.
    :param qos_profile: The QoS the endpoint announced (all UNKNOWN if not given).
    """

    __slots__ = ('node_name', 'node_namespace', 'topic_type', 'topic_type_hash', 'endpoint_type', 'endpoint_gid',
                 'qos_profile')

    def __init__(self, *, node_name: str = '', node_namespace: str = '', topic_type: str = '',
                 topic_type_hash: TypeHash | dict | None = None,
                 endpoint_type: TopicEndpointTypeEnum | int = TopicEndpointTypeEnum.INVALID,
                 endpoint_gid: list[int] | None = None, qos_profile: QoSProfile | dict | None = None) -> None:
        self.node_name = node_name
        self.node_namespace = node_namespace
        self.topic_type = topic_type
        self.topic_type_hash = TypeHash(**topic_type_hash) if isinstance(topic_type_hash, dict) \
            else topic_type_hash or TypeHash()
        self.endpoint_type = TopicEndpointTypeEnum(endpoint_type)
        self.endpoint_gid = list(endpoint_gid or [])
        self.qos_profile = QoSProfile(**qos_profile) if isinstance(qos_profile, dict) else qos_profile or _UNKNOWN_QOS

    def __eq__(self, other: Any) -> bool:
        return isinstance(other, TopicEndpointInfo) and all(
            getattr(self, slot) == getattr(other, slot) for slot in self.__slots__)

    def __str__(self) -> str:
        """The block `ros2 topic info -v` prints per endpoint."""
        qos = self.qos_profile
        depth = f' ({qos.depth})' if qos.history == HistoryPolicy.KEEP_LAST else ''
        return '\n'.join([
            f'Node name: {self.node_name}',
            f'Node namespace: {self.node_namespace}',
            f'Topic type: {self.topic_type}',
            f'Topic type hash: {self.topic_type_hash}',
            f'Endpoint type: {self.endpoint_type.name}',
            f"GID: {'.'.join(format(byte, '02x') for byte in self.endpoint_gid)}",
            'QoS profile:',
            f'  Reliability: {qos.reliability.name}',
            f'  History (Depth): {qos.history.name}{depth}',
            f'  Durability: {qos.durability.name}',
            f'  Lifespan: {qos.lifespan}',
            f'  Deadline: {qos.deadline}',
            f'  Liveliness: {qos.liveliness.name}',
            f'  Liveliness lease duration: {qos.liveliness_lease_duration}',
        ])
