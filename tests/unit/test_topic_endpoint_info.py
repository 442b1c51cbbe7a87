"""TopicEndpointInfo: rclpy's description of one endpoint, as a view over a graph record."""
from __future__ import annotations

from zros.graph import Entity, EntityKind
from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
from zros.topic_endpoint_info import TopicEndpointInfo, TopicEndpointTypeEnum
from zros.type_hash import TypeHash


def _record(kind: str, entity_id: int, qos: str = 'B:T:L3') -> Entity:
    return Entity(kind, 'a1b2c3d4e5f60718', 7, entity_id, '/robot', 'driver', '/robot/scan',
                  'sensor_msgs/msg/LaserScan', 'RIHS01_' + '0' * 64, qos)


def test_a_record_becomes_the_endpoint_rclpy_describes():
    info = TopicEndpointInfo.from_entity(_record(EntityKind.PUBLISHER, 3))
    assert (info.node_name, info.node_namespace, info.topic_type) == ('driver', '/robot', 'sensor_msgs/msg/LaserScan')
    assert info.endpoint_type == TopicEndpointTypeEnum.PUBLISHER
    assert info.qos_profile == QoSProfile(depth=3, reliability=2, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    assert len(info.endpoint_gid) == 16
    other = TopicEndpointInfo.from_entity(_record(EntityKind.SUBSCRIPTION, 4))
    assert other.endpoint_type == TopicEndpointTypeEnum.SUBSCRIPTION and other.endpoint_gid != info.endpoint_gid


def test_an_endpoint_without_qos_in_its_token_has_the_unknown_profile():
    info = TopicEndpointInfo.from_entity(_record(EntityKind.SUBSCRIPTION, 5, qos=''))
    assert info.qos_profile.history == HistoryPolicy.UNKNOWN
    assert info.qos_profile == TopicEndpointInfo().qos_profile


def test_fields_take_rclpy_spellings_and_print_as_topic_info_does():
    info = TopicEndpointInfo(endpoint_type=2, qos_profile={'depth': 4})
    assert info.endpoint_type is TopicEndpointTypeEnum.SUBSCRIPTION and info.qos_profile.depth == 4
    text = str(info)
    assert 'Topic type hash: INVALID' in text and '  History (Depth): KEEP_LAST (4)' in text
    assert str(TopicEndpointInfo()).splitlines()[4:6] == ['Endpoint type: INVALID', 'GID: ']


def test_an_endpoint_info_takes_its_hash_and_qos_as_dicts_as_rclpy_builds_them():
    info = TopicEndpointInfo(topic_type_hash={'version': 1, 'value': bytes(32)}, endpoint_type=2,
                             qos_profile={'depth': 4})
    assert info.topic_type_hash == TypeHash(1, bytes(32)) and info.qos_profile.depth == 4
    assert info.endpoint_type == TopicEndpointTypeEnum.SUBSCRIPTION
    assert info == TopicEndpointInfo(topic_type_hash=TypeHash(1, bytes(32)), endpoint_type=2,
                                     qos_profile=QoSProfile(depth=4))


def test_an_empty_endpoint_info_prints_as_rclpy_prints_it():
    assert str(TopicEndpointInfo()).splitlines() == [
        'Node name: ', 'Node namespace: ', 'Topic type: ', 'Topic type hash: INVALID', 'Endpoint type: INVALID',
        'GID: ', 'QoS profile:', '  Reliability: UNKNOWN', '  History (Depth): UNKNOWN', '  Durability: UNKNOWN',
        '  Lifespan: 0 nanoseconds', '  Deadline: 0 nanoseconds', '  Liveliness: UNKNOWN',
        '  Liveliness lease duration: 0 nanoseconds']
