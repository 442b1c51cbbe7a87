"""Jazzy's lifecycle launch shape: `LifecycleNode`, `EmitEvent(event=ChangeState(...))` and
`RegisterEventHandler(OnStateTransition(...))`, checked in the plan (`--print`), in the errors a
wrong use gives, and in real launches of the lifecycle demo's talker."""
from __future__ import annotations

import signal
import sys
from pathlib import Path

import pytest

from conftest import assert_clean_failure, run_cli, wait_until
from unit.test_launch_parse import write  # noqa: F401 - the fixture
from zros.launch import resolve
from zros.launch.plan import ChangeStateEffect, EventHandlerEffect, LogMessage, ProcessSpec

#: slam_toolbox's online_async_launch.py in shape (the ros2 branch), on the lifecycle demo's talker.
JAZZY_SHAPED = '''
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, LogInfo, RegisterEventHandler
from launch.conditions import IfCondition
from launch.events import matches_action
from launch.substitutions import AndSubstitution, LaunchConfiguration, NotSubstitution
from launch_ros.actions import LifecycleNode
from launch_ros.event_handlers import OnStateTransition
from launch_ros.events.lifecycle import ChangeState
from lifecycle_msgs.msg import Transition


def talker(name, fail_on):
    node = LifecycleNode(package='lifecycle', executable='lifecycle_talker', name=name, namespace='',
                         output='screen', parameters=[{'fail_on': fail_on}])
    autostart = IfCondition(AndSubstitution(LaunchConfiguration('autostart'),
                                            NotSubstitution(LaunchConfiguration('use_lifecycle_manager'))))
    return [
        node,
        EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(node),
                                    transition_id=Transition.TRANSITION_CONFIGURE), condition=autostart),
        RegisterEventHandler(OnStateTransition(
            target_lifecycle_node=node, start_state='configuring', goal_state='inactive',
            entities=[LogInfo(msg=[name, ' is activating']),
                      EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(node),
                                                  transition_id=Transition.TRANSITION_ACTIVATE))]),
            condition=autostart),
        RegisterEventHandler(OnStateTransition(target_lifecycle_node=node, goal_state='active',
                                               entities=[LogInfo(msg=[name, ' is active'])])),
    ]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('autostart', default_value='true'),
        DeclareLaunchArgument('use_lifecycle_manager', default_value='false'),
        *talker('good', ''),
        *talker('bad', 'on_activate'),
    ])
'''


def test_the_plan_has_the_transitions_and_their_handlers(write, tmp_path: Path):
    path = write('jazzy.launch.py', JAZZY_SHAPED)
    plan = resolve(str(path), log_dir=str(tmp_path / 'log'))
    good, configure, activating, active = plan.effects[:4]
    assert isinstance(good, ProcessSpec) and good.lifecycle and ('ZROS_LIFECYCLE_LAUNCH', '1') in good.env
    assert isinstance(configure, ChangeStateEffect) and (configure.transition_id, configure.label) == (1, 'configure')
    assert configure.matches(good) and not configure.matches(plan.effects[4])
    assert isinstance(activating, EventHandlerEffect) and activating.event == 'transition'
    assert activating.transition.start_state == 'configuring' and activating.transition.goal_state == 'inactive'
    assert activating.effects[0] == LogMessage('INFO', 'good is activating', activating.effects[0].origin)
    assert isinstance(activating.effects[1], ChangeStateEffect) and activating.effects[1].label == 'activate'
    assert active.transition.start_state is None and active.transition.goal_state == 'active'

    printed = run_cli('launch', str(path), '--print', '--log-dir', str(tmp_path / 'log'))
    assert printed.returncode == 0, printed
    for line in ('    env: ZROS_LIFECYCLE_LAUNCH=1', 'change state of [lifecycle_talker-1]: configure [1]',
                 'on state transition configuring -> inactive of [lifecycle_talker-1]:',
                 '  log [INFO]: good is activating', '  change state of [lifecycle_talker-1]: activate [3]',
                 'on state transition any state -> active of [lifecycle_talker-1]:',
                 'change state of [lifecycle_talker-2]: configure [1]'):
        assert line in printed.stdout.splitlines(), (line, printed.stdout)

    # With a lifecycle manager in charge, the launch requests nothing (the node still waits).
    managed = resolve(str(path), launch_arguments={'use_lifecycle_manager': 'true'}, log_dir=str(tmp_path / 'log'))
    assert not [e for e in managed.effects if isinstance(e, ChangeStateEffect)]
    assert [e.transition.goal_state for e in managed.effects if isinstance(e, EventHandlerEffect)] == ['active'] * 2


WRONG_USE = '''
from zros.launch import LaunchDescription
from zros.launch.actions import EmitEvent, LogInfo, RegisterEventHandler
from zros.launch.events import matches_action
from zros.launch_ros.actions import LifecycleNode, Node
from zros.launch_ros.event_handlers import OnStateTransition
from zros.launch_ros.events.lifecycle import ChangeState


def generate_launch_description():
    plain = Node(package='demo_nodes', executable='talker')
    node = LifecycleNode(package='lifecycle', executable='lifecycle_talker', name='lc', namespace='')
    return LaunchDescription([plain, node, {wrong}])
'''


@pytest.mark.parametrize('wrong, fragment', [
    ('EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(plain), transition_id=1))',
     'ChangeState: lifecycle_node_matcher: matches_action() names a Node; only a LifecycleNode has lifecycle '
     'transitions'),
    ('EmitEvent(event=ChangeState(lifecycle_node_matcher=matches_action(node), transition_id=9))',
     'ChangeState: transition_id: no public lifecycle transition with id 9 (ids: 1 (configure from unconfigured)'),
    ('RegisterEventHandler(OnStateTransition(target_lifecycle_node=node, goal_state="configured", entities=[]))',
     "OnStateTransition: goal_state: unknown state 'configured' (known: unknown, unconfigured, inactive, active"),
    ('RegisterEventHandler(OnStateTransition(target_lifecycle_node=plain, entities=[LogInfo(msg="x")]))',
     'OnStateTransition: target_lifecycle_node: expected a LifecycleNode action, got Node'),
])
def test_a_wrong_lifecycle_event_fails_in_one_line(write, tmp_path: Path, wrong: str, fragment: str):
    path = write('wrong.launch.py', WRONG_USE.replace('{wrong}', wrong))
    result = run_cli('launch', str(path), '--print', '--log-dir', str(tmp_path / 'log'))
    line = assert_clean_failure(result, str(path))
    assert fragment in line, line


def test_the_launch_drives_its_lifecycle_nodes(write, spawn, tmp_path: Path):
    """`good` is configured, then activated by the OnStateTransition handler; `bad` refuses to
    activate, and the launch says so; nobody else's transitions reach the handlers."""
    path = write('jazzy.launch.py', JAZZY_SHAPED)
    launch = spawn.command(sys.executable, '-m', 'zros', 'launch', str(path), '--log-dir', str(tmp_path / 'log'),
                           name='launch')
    launch.wait_for_output('[launch.user]: good is active', timeout=90)
    launch.wait_for_output("failed to make lifecycle transition 'activate' of /bad: ", timeout=30)
    out = launch.output()
    assert out.index('good is activating') < out.index("lifecycle transition 'activate' of /good done: now active") \
        < out.index('good is active'), out
    assert 'bad is activating' in out and 'bad is active' not in out, out
    launch.wait_for_output('[good]: Lifecycle publisher is active', timeout=10)
    for node, state in (('/good', 'active [3]'), ('/bad', 'inactive [2]')):
        result = run_cli('lifecycle', 'get', node, timeout=30)
        assert result.stdout.strip() == state, result
    # Transitions made from outside are not seen by the launch: its handler does not fire again.
    for transition in ('deactivate', 'activate'):
        assert run_cli('lifecycle', 'set', '/good', transition, timeout=30).returncode == 0
    launch.signal(signal.SIGINT)
    assert launch.wait(30) == 0, launch.output()
    assert launch.output().count('[launch.user]: good is active') == 1, launch.output()


def test_lifecycle_set_waits_for_a_node_that_is_not_there_yet(zros_cli, spawn):
    result = zros_cli('lifecycle', 'set', '/late', 'configure', '--wait', '0.5', timeout=30)
    assert_clean_failure(result, 'Node not found (waited 0.5 s)')
    spawn.run('lifecycle', 'lifecycle_talker', '--ros-args', '-r', '__node:=late')
    result = zros_cli('lifecycle', 'set', '/late', 'configure', '--wait', '60', timeout=90)
    assert result.returncode == 0 and result.stdout.strip() == 'Transitioning successful', result
    wait_until(lambda: zros_cli('lifecycle', 'get', '/late', timeout=30).stdout.strip() == 'inactive [2]', 30,
               message='/late configured')
