"""Which containers LoadComposableNodes loads into with LoadNode requests (those the launch does
not start) and which it runs as processes (those it does), and launch_ros's reading of a
parameter file for a request: the node's own entry wins over `/**`, and a file with no
`ros__parameters` is the node's parameters as it stands."""
from __future__ import annotations

import textwrap

from unit.test_launch_parse import plan_of, processes, write  # noqa: F401 - fixtures
from zros.launch import LaunchContext
from zros.launch.load_node import get_composable_node_load_request
from zros.launch.plan import TaskEffect
from zros.launch_ros.descriptions import ComposableNode


def test_a_container_the_launch_does_not_start_gets_a_load_task(plan_of):
    plan = plan_of('''
        launch:
        - load_composable_node:
            target: camera_container
            composable_node:
            - {pkg: image_proc, plugin: image_proc::RectifyNode, name: rectify}
            - {pkg: image_proc, plugin: image_proc::ResizeNode, name: resize}
        ''')
    assert processes(plan) == []
    [task] = [effect for effect in plan.effects if isinstance(effect, TaskEffect)]
    assert task.label == ("load 2 composable nodes into container '/camera_container' "
                          '(service /camera_container/_container/load_node)')
    assert task.label in plan.describe()


def test_a_container_node_of_the_launch_keeps_running_composable_nodes_as_processes(plan_of):
    plan = plan_of('''
        launch:
        - node: {pkg: rclcpp_components, exec: component_container_isolated, name: nav2_container}
        - load_composable_node:
            target: /nav2_container
            composable_node: [{pkg: demo_nodes, plugin: demo_nodes::Talker, name: talker}]
        ''')
    assert [spec.node.executable for spec in processes(plan)] == ['component_container_isolated', 'talker']
    assert not any(isinstance(effect, TaskEffect) for effect in plan.effects)


def request_parameters(tmp_path, text: str, name: str, namespace: str) -> list[tuple[str, object]]:
    path = tmp_path / 'params.yaml'
    path.write_text(textwrap.dedent(text))
    description = ComposableNode(package='p', plugin='p::P', name=name, namespace=namespace, parameters=[path])
    request = get_composable_node_load_request(description, LaunchContext())
    from zros.parameter import parameter_value_to_python
    return [(p.name, parameter_value_to_python(p.value)) for p in request.parameters]


def test_the_nodes_own_entry_wins_over_the_wildcard_wherever_it_is_written(tmp_path):
    text = '''
        /cams:
          /left:
            ros__parameters: {fps: 30, mode: mono}
        /**:
          ros__parameters: {fps: 10, exposure: 4}
        '''
    assert request_parameters(tmp_path, text, 'left', 'cams') == [('fps', 30), ('exposure', 4), ('mode', 'mono')]
    assert request_parameters(tmp_path, text, 'right', 'cams') == [('fps', 10), ('exposure', 4)]


def test_a_file_without_ros_parameters_is_the_nodes_parameters(tmp_path):
    text = '''
        fps: 30
        lens: {model: pinhole}
        '''
    assert request_parameters(tmp_path, text, 'left', 'cams') == [('fps', 30), ('lens.model', 'pinhole')]
