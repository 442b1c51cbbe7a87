"""launch_ros's Node under a LaunchService started from code, as launch_ros's users and tests
run it: a node whose package is missing fails the run with a return code, inline parameters
reach the node without a log directory, and talker_qos stops after its cycles."""
from __future__ import annotations

from zros.launch import LaunchDescription, LaunchService
from zros.launch_ros.actions import Node


def run(*actions) -> int:
    service = LaunchService()
    service.include_launch_description(LaunchDescription(list(actions)))
    return service.run()


def test_a_node_of_a_missing_package_fails_the_run_with_one_line(capfd):
    assert run(Node(package='no_such_package', executable='node')) == 1
    assert "package 'no_such_package' not found" in capfd.readouterr().err


def test_inline_parameters_reach_a_node_started_by_a_launch_service(capfd):
    probe = ('import sys, yaml; i = sys.argv.index("--params-file"); '
             'print("rate =", yaml.safe_load(open(sys.argv[i + 1]))["/**"]["ros__parameters"]["rate"])')
    node = Node(executable='python3', arguments=['-c', probe], parameters=[{'rate': 7}], output='screen')
    assert run(node) == 0
    assert 'rate = 7' in capfd.readouterr().out


def test_talker_qos_stops_after_its_cycles(capfd):
    talker = Node(package='demo_nodes_py', executable='talker_qos', arguments=['--number_of_cycles', '1'],
                  name='talker', namespace='qos', output='screen')
    assert run(talker) == 0
    assert "Publishing: 'Hello World: 1'" in capfd.readouterr().out
