"""rclpy.topic_endpoint_info: one publisher or subscription as `get_publishers_info_by_topic` and
`zros topic info -v` describe it.

A view over a graph record (zros.graph.Entity), in rclpy's shape: the node, the topic's type and
its hash, the kind of endpoint, a gid and the QoS profile the endpoint asked for. zros endpoints
have no DDS gid; theirs is made of the session id, the node's and the entity's numbers, so that
it tells endpoints apart as a gid does.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass, field

from zros.graph import Entity, EntityKind
from zros.qos import HistoryPolicy, QoSProfile, qos_profile_unknown, to_profile
from zros.type_hash import TypeHash

__all__ = ['TopicEndpointTypeEnum', 'TopicEndpointInfo']


class TopicEndpointTypeEnum(enum.IntEnum):
    """Which side of a topic an endpoint is (rmw's rmw_endpoint_type_t values)."""
    INVALID = 0
    PUBLISHER = 1
    SUBSCRIPTION = 2


def _unknown_qos() -> QoSProfile:
    return to_profile(qos_profile_unknown)


@dataclass
class TopicEndpointInfo:
    """One endpoint of a topic. All fields are keywords with 'unknown' defaults, as rclpy's;
    `topic_type_hash` is a TypeHash (INVALID where the graph announces no RIHS hash, see
    zros.type_hash; its ``version``/``value`` as a dict are taken too)."""

    node_name: str = ''
    node_namespace: str = ''
    topic_type: str = ''
    topic_type_hash: TypeHash = field(default_factory=TypeHash)
    endpoint_type: TopicEndpointTypeEnum = TopicEndpointTypeEnum.INVALID
    endpoint_gid: list[int] = field(default_factory=list)
    qos_profile: QoSProfile = field(default_factory=_unknown_qos)

    def __setattr__(self, name: str, value: object) -> None:
        # rclpy takes the endpoint kind as an int and a profile as QoSProfile's keywords too.
        if name == 'endpoint_type':
            value = TopicEndpointTypeEnum(value)
        elif name == 'qos_profile' and isinstance(value, dict):
            value = QoSProfile(**value)
        elif name == 'topic_type_hash' and isinstance(value, dict):
            value = TypeHash(**value)
        object.__setattr__(self, name, value)

    @classmethod
    def from_entity(cls, entity: Entity) -> TopicEndpointInfo:
        """The endpoint a graph record describes (a publisher's or a subscription's token)."""
        kinds = {EntityKind.PUBLISHER: TopicEndpointTypeEnum.PUBLISHER,
                 EntityKind.SUBSCRIPTION: TopicEndpointTypeEnum.SUBSCRIPTION}
        return cls(node_name=entity.node_name, node_namespace=entity.namespace, topic_type=entity.type,
                   topic_type_hash=TypeHash.from_string(entity.type_hash),
                   endpoint_type=kinds.get(entity.kind, TopicEndpointTypeEnum.INVALID),
                   endpoint_gid=_gid(entity),
                   qos_profile=QoSProfile.from_token(entity.qos) if entity.qos else _unknown_qos())

    def __str__(self) -> str:
        """The block `ros2 topic info -v` prints for the endpoint."""
        qos = self.qos_profile
        history = qos.history.name
        if qos.history == HistoryPolicy.KEEP_LAST:
            history += f' ({qos.depth})'
        return '\n'.join([
            f'Node name: {self.node_name}',
            f'Node namespace: {self.node_namespace}',
            f'Topic type: {self.topic_type}',
            f'Topic type hash: {self.topic_type_hash}',
            f'Endpoint type: {self.endpoint_type.name}',
            f"GID: {'.'.join(f'{byte:02x}' for byte in self.endpoint_gid)}",
            'QoS profile:',
            f'  Reliability: {qos.reliability.name}',
            f'  History (Depth): {history}',
            f'  Durability: {qos.durability.name}',
            f'  Lifespan: {qos.lifespan}',
            f'  Deadline: {qos.deadline}',
            f'  Liveliness: {qos.liveliness.name}',
            f'  Liveliness lease duration: {qos.liveliness_lease_duration}',
        ])


def _gid(entity: Entity) -> list[int]:
    """16 bytes, as an rmw gid: 8 of the session id's, then the node's and the entity's numbers
    (4 bytes each, big-endian)."""
    try:
        session = bytes.fromhex(entity.zid.rjust(16, '0')[-16:])
    except ValueError:
        session = bytes(8)
    return list(session + entity.node_id.to_bytes(4, 'big') + entity.entity_id.to_bytes(4, 'big'))
