"""Python launch files (`*.launch.py`) planned in process by `resolve()`: the shipped YAML launch
files and their Python and XML twins give one plan, and the plan holds what the actions ask (the
same files run by `zros launch`: tests/integration/test_launch_python.py)."""
from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from conftest import REPO
from unit.test_launch_parse import write  # noqa: F401 - the fixture
from zros.launch import LaunchError, resolve
from zros.launch.plan import EventHandlerEffect, GeneratedParams, LogMessage, ProcessSpec, ShutdownEffect, TimerEffect


def normalized_plan(text: str) -> str:
    """`--print` output without what differs between twins: file names and lines."""
    return re.sub(r'\S+\.launch\.(py|yaml|xml)(:\d+)?', 'FILE', text)


def twins() -> list[tuple[str, dict[str, str]]]:
    """Every example YAML launch file, and every package YAML launch file that has a Python twin,
    with the launch arguments it needs (relative to the repository)."""
    needs = {'nodes/turtlebot3_gazebo/launch/robot_world': {'world': 'turtlebot3_world'},
             'nodes/turtlebot3_gazebo/launch/turtlebot3_world': {'view': 'true', 'x_pose': '0.5', 'use_sim_time': 'True'}}
    stems = [p.with_suffix('').with_suffix('') for p in (REPO / 'configs').glob('*.launch.yaml')]
    stems += [p.with_suffix('').with_suffix('') for p in (REPO / 'nodes').glob('*/launch/*.launch.yaml')
              if p.with_suffix('.py').exists()]
    return sorted((str(stem.relative_to(REPO)), needs.get(str(stem.relative_to(REPO)), {})) for stem in stems)


@pytest.mark.parametrize('name, arguments', twins())
def test_every_shipped_yaml_launch_file_has_twins_with_the_same_plan(name: str, arguments: dict[str, str],
                                                                   tmp_path: Path):
    """A Python twin for each, and an XML twin for every example in configs/: the front ends agree."""
    yaml_plan = resolve(str(REPO / f'{name}.launch.yaml'), launch_arguments=arguments, log_dir=str(tmp_path))
    twins = ['py', 'xml'] if name.startswith('configs/') else ['py']
    for extension in twins:
        plan = resolve(str(REPO / f'{name}.launch.{extension}'), launch_arguments=arguments, log_dir=str(tmp_path))
        assert normalized_plan(plan.describe()) == normalized_plan(yaml_plan.describe()), extension
        assert [replace(e, origin=None) for e in plan.effects] == [replace(e, origin=None) for e in yaml_plan.effects]


def test_shipped_package_launch_file_uses_its_share_directory(tmp_path: Path):
    plan = resolve(str(REPO / 'nodes' / 'demo_nodes' / 'launch' / 'talker_listener.launch.py'),
                   launch_arguments={'text': 'hi'}, log_dir=str(tmp_path))
    talker = [e for e in plan.effects if isinstance(e, ProcessSpec)][0]
    assert talker.params[0].path == str(REPO / 'nodes' / 'demo_nodes' / 'param' / 'talker.yaml')
    assert talker.params[1] == GeneratedParams({'/**': {'ros__parameters': {'published_text': 'hi'}}})


def plan_of(write, tmp_path: Path, text: str, **arguments: str):
    path = write('t.launch.py', text)
    return resolve(str(path), launch_arguments=arguments, log_dir=str(tmp_path / 'log'))


HEADER = '''
import sys
from typing import List
from zros.launch import LaunchDescription
from zros.launch.actions import *
from zros.launch.conditions import *
from zros.launch.event_handlers import *
from zros.launch.events import Shutdown as ShutdownEvent
from zros.launch.substitutions import *
from zros.launch_ros.actions import *
from zros.launch_ros.descriptions import ComposableNode
from zros.launch_ros.parameter_descriptions import *
from zros.launch_ros.substitutions import *
'''


def test_node_options_and_parameter_rules(write, tmp_path: Path):
    plan = plan_of(write, tmp_path, HEADER + '''
def generate_launch_description():
    return LaunchDescription([
        SetEnvironmentVariable('A', '1'),
        Node(package='demo_nodes', executable='talker', name='t', namespace='/ns', exec_name='speaker',
             respawn=True, respawn_delay=2.5, sigterm_timeout='3', additional_env={'B': '2'},
             ros_arguments=['--log-level', 'debug'], prefix='nice -n 5',
             parameters=[{'plain': '1', 'typed': TextSubstitution(text='1'), 'forced': ParameterValue(TextSubstitution(text='1'), value_type=int),
                          'listed': [1, 2.5], 'strings': ['a', 'b'], 'flag': True,
                          'typed_list': ParameterValue(TextSubstitution(text='[1, 2]'), value_type=List[int])}]),
        ExecuteProcess(cmd=['echo', 'a b'], name='shell_free'),
        ExecuteProcess(cmd=['echo hi && true'], shell=True, name='in_shell'),
    ])
''')
    node, echo, shell = [e for e in plan.effects if isinstance(e, ProcessSpec)]
    assert node.label == 'speaker'
    assert node.cmd_head[:2] == ('nice', '-n') and ('--ros-args', '--log-level', 'debug') == tuple(
        node.cmd_head[node.cmd_head.index('--ros-args'):][:3])
    assert node.respawn and node.respawn_delay == 2.5 and node.sigterm_timeout == 3.0
    assert dict(node.env) == {'A': '1', 'B': '2'}
    assert node.params[0].document['/**']['ros__parameters'] == {
        'plain': '1', 'typed': 1, 'forced': 1, 'listed': [1.0, 2.5], 'strings': ['a', 'b'], 'flag': True,
        'typed_list': [1, 2]}
    assert echo.cmd_head == ('echo', 'a b')                      # one argument per item
    assert shell.cmd_head[-3:] == ('/bin/sh', '-c', 'echo hi && true')


def test_timer_event_handlers_and_shutdown_in_the_plan(write, tmp_path: Path):
    plan = plan_of(write, tmp_path, HEADER + '''
def generate_launch_description():
    worker = ExecuteProcess(cmd=['true'], name='worker')
    return LaunchDescription([
        worker,
        RegisterEventHandler(OnProcessExit(target_action=worker, on_exit=[EmitEvent(event=ShutdownEvent(reason='done'))])),
        RegisterEventHandler(OnProcessStart(target_action=worker, on_start=lambda event, context: None)),
        TimerAction(period=1.5, actions=[LogInfo(msg='later')]),
        ExecuteProcess(cmd=['true'], name='stopper', on_exit=Shutdown()),
    ])
''')
    worker, on_exit, on_start, timer, stopper = plan.effects
    assert isinstance(on_exit, EventHandlerEffect) and on_exit.event == 'exit' and on_exit.matches(worker)
    assert on_exit.effects == [ShutdownEffect('done', on_exit.effects[0].origin)]
    assert on_start.deferred is not None and on_start.effects_for('worker-1', 1, None, ['true']) == []
    assert timer == TimerEffect(1.5, [LogMessage('INFO', 'later', timer.effects[0].origin)], timer.origin)
    assert stopper.on_exit_shutdown
    printed = plan.describe()
    assert 'on exit of [worker-1]:\n  shutdown: done' in printed
    assert 'after 1.5 s:\n  log [INFO]: later' in printed


def test_undeclared_arguments_read_by_the_launch_are_accepted(write, tmp_path: Path):
    """ROS 2 launch files (turtlebot3_world.launch.py) read `x_pose` with a default and no
    DeclareLaunchArgument; `x_pose:=1.0` must reach them. A name nothing reads is a typo."""
    text = HEADER + '''
def generate_launch_description():
    x = LaunchConfiguration('x_pose', default='-2.0')
    return LaunchDescription([OpaqueFunction(function=lambda context: [LogInfo(msg=context.launch_configurations.get('y', '-'))]),
                              LogInfo(msg=['x=', x])])
'''
    plan = plan_of(write, tmp_path, text, x_pose='1.0', y='3')
    assert [e.message for e in plan.effects] == ['3', 'x=1.0']
    with pytest.raises(LaunchError, match="unknown launch argument 'x_poze'"):
        plan_of(write, tmp_path, text, x_poze='1.0')


def test_composable_nodes_run_as_processes(write, tmp_path: Path):
    plan = plan_of(write, tmp_path, HEADER + '''
def generate_launch_description():
    return LaunchDescription([ComposableNodeContainer(
        name='container', namespace='', package='rclcpp_components', executable='component_container',
        composable_node_descriptions=[
            ComposableNode(package='demo_nodes', plugin='demo_nodes::Talker', name='talker',
                           remappings=[('chatter', 'news')], parameters=[{'x': 1}]),
            ComposableNode(package='demo_nodes', plugin='demo_nodes::Listener', name='listener',
                           condition=IfCondition('false')),
        ])])
''')
    note, talker = plan.effects
    assert note.message == ("zros has no component containers: composable node 'talker' of container "
                            "'/container' runs as its own process")
    assert talker.node.executable == 'talker' and '-r' in talker.cmd_head and 'chatter:=news' in talker.cmd_head


def test_turtlebot3_gazebos_spawn_and_robot_state_publisher_launch_files_take_upstreams_arguments(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """spawn_turtlebot3.launch.py spawns $TURTLEBOT3_MODEL's model.sdf where x_pose and y_pose
    say; robot_state_publisher.launch.py reads the package's URDF of that model."""
    monkeypatch.setenv('TURTLEBOT3_MODEL', 'waffle')
    launch = REPO / 'nodes' / 'turtlebot3_gazebo' / 'launch'
    plan = resolve(str(launch / 'spawn_turtlebot3.launch.py'), launch_arguments={'x_pose': '-2.0', 'y_pose': '-0.5'},
                   log_dir=str(tmp_path))
    spawner, = [e for e in plan.effects if isinstance(e, ProcessSpec)]
    head = spawner.cmd_head
    model = REPO / 'nodes' / 'turtlebot3_gazebo' / 'models' / 'turtlebot3_waffle' / 'model.sdf'
    assert head[head.index('-entity') + 1] == 'waffle' and Path(head[head.index('-file') + 1]) == model
    assert (head[head.index('-x') + 1], head[head.index('-y') + 1], head[head.index('-z') + 1]) == ('-2.0', '-0.5', '0.01')
    plan = resolve(str(launch / 'robot_state_publisher.launch.py'), launch_arguments={'use_sim_time': 'true'},
                   log_dir=str(tmp_path))
    publisher, = [e for e in plan.effects if isinstance(e, ProcessSpec)]
    assert publisher.label == 'robot_state_publisher'
    assert 'turtlebot3_waffle' in str(publisher.params)
