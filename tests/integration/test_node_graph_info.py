"""The node's endpoint infos and node listings in rclpy's shape (TopicEndpointInfo, enclaves)."""
from __future__ import annotations

from interfaces.std_msgs.msg import String
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from zros.topic_endpoint_info import TopicEndpointInfo, TopicEndpointTypeEnum
from zros.type_hash import TypeHash


def test_endpoint_infos_name_node_type_kind_and_the_announced_qos(context):
    node = Node('informer', namespace='/info', context=context)
    offered = QoSProfile(depth=3, reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_publisher(String, 'status', offered)
    node.create_subscription(String, 'status', lambda msg: None, 7)
    publisher, = node.get_publishers_info_by_topic('status')
    subscription, = node.get_subscriptions_info_by_topic('/info/status')
    assert isinstance(publisher, TopicEndpointInfo)
    assert (publisher.node_name, publisher.node_namespace, publisher.topic_type) == ('informer', '/info', 'std_msgs/msg/String')
    assert publisher.endpoint_type == TopicEndpointTypeEnum.PUBLISHER
    assert subscription.endpoint_type == TopicEndpointTypeEnum.SUBSCRIPTION
    assert publisher.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
    assert publisher.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert subscription.qos_profile.depth == 7
    assert publisher.endpoint_gid and publisher.endpoint_gid != subscription.endpoint_gid
    assert publisher.topic_type_hash == TypeHash()   # zros announces its own hash, no RIHS01 one
    assert 'Endpoint type: PUBLISHER' in str(publisher) and 'Reliability: BEST_EFFORT' in str(publisher)
    assert ('informer', '/info', '/') in node.get_node_names_and_namespaces_with_enclaves()
    node.destroy_node()

