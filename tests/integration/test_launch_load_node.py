"""LoadComposableNodes aimed at a component container the launch does not start: the container
(here a node of the test's own, serving `~/_container/load_node`) gets one LoadNode request per
node, in order; the launch logs each answer and waits for them before it ends, and a container
that never shows up fails the launch after a bounded wait instead of hanging it."""
from __future__ import annotations

import pytest

from conftest import background_node
from zros.launch import LaunchDescription, LaunchService
from zros.launch_ros.actions import LoadComposableNodes
from zros.launch_ros.descriptions import ComposableNode
from zros.launch_ros.utilities import get_node_name_count


def run(*actions) -> tuple[int, LaunchService]:
    service = LaunchService()
    service.include_launch_description(LaunchDescription(list(actions)))
    return service.run(), service


def load(*nodes: ComposableNode, target: str = '/arm_container') -> LoadComposableNodes:
    return LoadComposableNodes(target_container=target, composable_node_descriptions=list(nodes))


@pytest.fixture
def container(domain):
    """A container of our own that refuses plugins named 'broken::Plugin'."""
    from interfaces.composition_interfaces.srv import LoadNode
    received = []

    def on_load(request, response):
        received.append(request)
        response.success = request.plugin_name != 'broken::Plugin'
        response.error_message = '' if response.success else 'no such plugin'
        response.full_node_name = f"{request.node_namespace.rstrip('/')}/{request.node_name}"
        return response

    with background_node('arm_container') as node:
        node.create_service(LoadNode, '~/_container/load_node', on_load)
        yield received


def test_requests_go_to_the_container_in_order_and_the_launch_waits_for_the_answers(container, capfd):
    code, service = run(load(
        ComposableNode(package='arm', plugin='arm::Driver', name='driver', namespace='arm',
                       parameters=[{'rate': 50}], remappings=[('joints', '/arm/joints')]),
        ComposableNode(package='arm', plugin='broken::Plugin', name='gripper', namespace='arm')))
    assert code == 0
    assert [(r.plugin_name, r.node_name, r.node_namespace) for r in container] == [
        ('arm::Driver', 'driver', '/arm'), ('broken::Plugin', 'gripper', '/arm')]
    assert list(container[0].remap_rules) == ['joints:=/arm/joints']
    assert [(p.name, p.value.integer_value) for p in container[0].parameters] == [('rate', 50)]
    # only the node the container loaded counts as one of the launch's
    assert get_node_name_count(service.context, '/arm/driver') == 1
    assert get_node_name_count(service.context, '/arm/gripper') == 0
    out = capfd.readouterr().out
    assert "Loaded node '/arm/driver' in container '/arm_container'" in out
    assert ("Failed to load node '/arm/gripper' of type 'broken::Plugin' in container '/arm_container': "
            'no such plugin') in out


def test_a_container_that_never_appears_fails_the_launch_after_the_bounded_wait(domain, monkeypatch, capfd):
    import zros.launch.load_node
    monkeypatch.setattr(zros.launch.load_node, 'SERVICE_WAIT_S', 1.0)
    code, _ = run(load(ComposableNode(package='arm', plugin='arm::Driver', name='driver'), target='nobody'))
    assert code == 1
    out = capfd.readouterr().out
    assert "no container offers '/nobody/_container/load_node' after 1 s" in out
