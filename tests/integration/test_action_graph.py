"""rclpy.action's graph functions: which actions the graph holds, and which node has them."""
from __future__ import annotations

from zros.action import (ActionClient, ActionServer, get_action_client_names_and_types_by_node,
                         get_action_names_and_types, get_action_server_names_and_types_by_node)
from zros.node import Node
from zros.testing import spin_until

from interfaces.example_interfaces.action import Fibonacci


def test_action_graph_functions(make_context):
    ctx = make_context()
    observer = Node('observer', context=ctx)
    node = Node('owner', namespace='/ns', context=ctx)
    ActionClient(node, Fibonacci, 'used')
    ActionServer(node, Fibonacci, 'served', lambda h: Fibonacci.Result())
    fib = 'example_interfaces/action/Fibonacci'
    spin_until(observer, lambda: len(get_action_names_and_types(observer)) == 2, timeout=10)
    assert get_action_names_and_types(observer) == [('/ns/served', [fib]), ('/ns/used', [fib])]
    assert get_action_client_names_and_types_by_node(observer, 'owner', '/ns') == [('/ns/used', [fib])]
    assert get_action_server_names_and_types_by_node(observer, 'owner', '/ns') == [('/ns/served', [fib])]
    assert get_action_server_names_and_types_by_node(observer, 'observer', '/') == []
