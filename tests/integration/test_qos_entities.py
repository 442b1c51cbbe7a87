"""QoS profiles on live entities: what publishers and subscriptions keep, and what the graph
reports (the profiles themselves: tests/unit/test_qos.py)."""
from __future__ import annotations

import dataclasses

import pytest

from unit.test_qos import BEST_EFFORT, TRANSIENT_LOCAL
from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy


def test_profiles_are_mutable_as_rclpys_and_entities_keep_a_copy(context):
    from interfaces.std_msgs.msg import String
    from zros.node import Node
    profile = QoSProfile(depth=3)
    assert profile == QoSProfile(depth=3) and dataclasses.replace(profile, depth=4).depth == 4
    publisher = Node('qos_copy', context=context).create_publisher(String, 'qos_copy', profile)
    profile.reliability = 2          # plain ints, as rclpy takes them
    profile.durability = DurabilityPolicy.SYSTEM_DEFAULT
    assert profile.reliability is BEST_EFFORT and profile.durability == DurabilityPolicy.SYSTEM_DEFAULT
    assert publisher.qos_profile.reliability == ReliabilityPolicy.RELIABLE, 'made before the change'
    with pytest.raises(ValueError, match='depth'):
        profile.depth = -1
    with pytest.raises(TypeError):
        hash(profile)


def test_profiles_reach_the_graph(context):
    """The QoS a publisher asked for is what the graph (and `topic info -v`) shows."""
    from zros.topic_endpoint_info import TopicEndpointTypeEnum
    from zros.node import Node
    from interfaces.std_msgs.msg import String
    node = Node('qos_node', context=context)
    node.create_publisher(String, '/q', QoSProfile(depth=3, reliability=BEST_EFFORT, durability=TRANSIENT_LOCAL))
    node.create_subscription(String, '/q', lambda m: None, QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0))
    # (the graph learns about this process's own entities asynchronously: see test_pubsub's
    # test_own_entities_are_in_the_graph_at_once)
    assert context.graph.wait_for(lambda es: sum(e.name == '/q' for e in es) == 2, 5.0)
    pubs = node.get_publishers_info_by_topic('/q')
    subs = node.get_subscriptions_info_by_topic('/q')
    assert [e.qos_profile for e in pubs] == \
        [QoSProfile(depth=3, reliability=BEST_EFFORT, durability=TRANSIENT_LOCAL)]
    assert [e.qos_profile.to_token() for e in subs] == ['R:V:A']
    assert pubs[0].endpoint_type == TopicEndpointTypeEnum.PUBLISHER
    assert 'Endpoint type: SUBSCRIPTION' in str(subs[0]) and len(set(map(tuple, (pubs[0].endpoint_gid,
                                                                                  subs[0].endpoint_gid)))) == 2


def test_rclpy_helper_writes_the_overrides_into_the_callers_profile(context):
    """`_declare_qos_parameters` (rclpy's private helper, which tools call) changes the profile it
    is given; the public declare_qos_parameters returns a copy."""
    from zros.node import Node
    from zros.parameter import Parameter
    from zros.publisher import Publisher
    from zros.qos_overriding_options import QoSOverridingOptions, _declare_qos_parameters
    node = Node('qos_helper', context=context,
                parameter_overrides=[Parameter('qos_overrides./t.publisher.reliability', value='best_effort')])
    profile = QoSProfile(depth=4)
    _declare_qos_parameters(Publisher, node, '/t', profile, QoSOverridingOptions.with_default_policies())
    assert (profile.reliability, profile.depth) == (BEST_EFFORT, 4)
    assert node.get_parameter('qos_overrides./t.publisher.history').value == 'keep_last'
