"""TopicEndpointInfo as rclpy's tools build and print it."""
from __future__ import annotations

from zros.qos import QoSProfile
from zros.topic_endpoint_info import TopicEndpointInfo, TopicEndpointTypeEnum
from zros.type_hash import TypeHash


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
