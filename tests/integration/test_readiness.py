"""A server is ready when a request sent now reaches it, not merely when the graph lists it:
the graph (liveliness tokens) can learn of a server before Zenoh's routing knows its queryable.
These tests hold the two apart on purpose: a graph entry with no queryable behind it."""
from __future__ import annotations

from zros.action import ActionClient, ActionServer
from zros.graph import EntityKind
from zros.node import Node
from zros.testing import spin_until


def test_a_listed_service_without_a_queryable_is_not_ready(make_context):
    from interfaces.example_interfaces.srv import AddTwoInts
    server = Node('ghost_server', context=make_context())
    client = Node('ghost_client', context=make_context()).create_client(AddTwoInts, '/ghost')
    ghost = server._declare_entity(EntityKind.SERVICE, '/ghost', AddTwoInts)  # listed, not served
    assert client._node.context.graph.wait_for(lambda es: any(e.name == '/ghost' for e in es), 10)
    assert not client.service_is_ready() and not client.wait_for_service(timeout_sec=0.5)
    server._undeclare_entity(ghost)
    server.create_service(AddTwoInts, '/ghost', lambda req, resp: setattr(resp, 'sum', req.a + req.b) or resp)
    assert client.wait_for_service(timeout_sec=10) and client.service_is_ready()
    answer = client.call_async(AddTwoInts.Request(a=2, b=3))
    spin_until(server, answer.done, timeout=10)
    assert answer.result().sum == 5


def test_an_action_server_is_ready_when_all_its_services_are(make_context):
    from interfaces.example_interfaces.action import Fibonacci
    server = Node('half_server', context=make_context())
    client = ActionClient(Node('half_client', context=make_context()), Fibonacci, '/fib')
    ghost = server._declare_entity(EntityKind.ACTION_SERVER, '/fib', Fibonacci)  # no services yet
    assert client._node.context.graph.wait_for(
        lambda es: any(e.kind == EntityKind.ACTION_SERVER for e in es), 10)
    assert not client.server_is_ready() and not client.wait_for_server(timeout_sec=0.5)
    server._undeclare_entity(ghost)
    ActionServer(server, Fibonacci, '/fib', lambda handle: Fibonacci.Result())
    assert client.wait_for_server(timeout_sec=10) and client.server_is_ready()
