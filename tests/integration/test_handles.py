"""rclpy's opaque handles on zros objects: valid while the object lives, held with `with`, and
InvalidHandle once it is destroyed; a destroy during a `with` block waits for the block."""
from __future__ import annotations

import pytest

from zros.exceptions import InvalidHandle
from zros.node import Node

from interfaces.std_msgs.msg import String
from interfaces.std_srvs.srv import Trigger


def _entities(node):
    """One entity of each kind with a handle, by kind, with the node's destroy for it."""
    return {
        'publisher': (node.create_publisher(String, 'out', 1), node.destroy_publisher),
        'subscription': (node.create_subscription(String, 'in', lambda msg: None, 1), node.destroy_subscription),
        'service': (node.create_service(Trigger, 'srv', lambda req, res: res), node.destroy_service),
        'client': (node.create_client(Trigger, 'srv'), node.destroy_client),
        'timer': (node.create_timer(1.0, lambda: None), node.destroy_timer),
        'guard condition': (node.create_guard_condition(lambda: None), node.destroy_guard_condition),
    }


def test_every_entity_handle_is_invalid_after_its_destroy(context):
    node = Node('handles', context=context)
    for entity, destroy in _entities(node).values():
        with entity.handle:
            pass
        destroy(entity)
        with pytest.raises(InvalidHandle, match='has been destroyed'):
            with entity.handle:
                pass


def test_a_held_publisher_leaves_the_graph_when_the_block_ends(context):
    node = Node('holder', context=context)
    publisher = node.create_publisher(String, 'held', 1)
    with publisher.handle:
        node.destroy_publisher(publisher)
        assert not publisher.handle.valid
        assert '/held' in dict(node.get_topic_names_and_types())   # still declared in the block
    assert '/held' not in dict(node.get_topic_names_and_types())


def test_node_and_context_handles(make_context):
    context = make_context()
    node = Node('owner', context=context)
    assert context.handle is not None and context.handle.valid
    node.destroy_node()
    with pytest.raises(InvalidHandle):
        with node.handle:
            pass
    context.destroy()
    assert not context.handle.valid and not context.ok()


def test_the_parameter_events_publisher_is_listed(context):
    """As rclpy's node lists the /parameter_events publisher it creates among its publishers."""
    node = Node('lister', context=context)
    assert [p.topic_name for p in node.publishers] == ['/parameter_events']
    node.destroy_node()
    assert list(node.publishers) == []
