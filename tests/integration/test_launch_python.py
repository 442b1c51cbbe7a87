"""Python launch files (`*.launch.py`): the same model as YAML, checked through `resolve()` and
through real `zros launch` runs with real node processes in a private domain (the plans alone,
in process: tests/unit/test_launch_python_plans.py).

A probe package (on ZROS_NODE_PATH) has one node, `report`, that prints what it was started
with (fully qualified name, parameters, where `chatter` resolves to, its arguments) and exits,
so a test can see what the launch gave it.
"""
from __future__ import annotations

import json
import os
import re
import signal
import sys
import textwrap
import time
from pathlib import Path

import pytest

from conftest import assert_clean_failure, run_cli
from unit.test_launch_parse import write  # noqa: F401 - the fixture

REPO = Path(__file__).resolve().parents[2]

REPORT_NODE = '''
import json
import os
import sys

import zros
from zros.node import Node


def main():
    zros.init()
    node = Node('report', automatically_declare_parameters_from_overrides=True)
    args = sys.argv[1:sys.argv.index('--ros-args')] if '--ros-args' in sys.argv else sys.argv[1:]
    params = {name: p.value for name, p in node.get_parameters_by_prefix('').items()}
    print('REPORT ' + json.dumps({'fqn': node.get_fully_qualified_name(), 'params': params,
                                  'chatter': node.resolve_topic_name('chatter'), 'args': args,
                                  'unused': node.resolve_topic_name('/unused'),
                                  'env': os.environ.get('PROBE_ENV')}, sort_keys=True), flush=True)
    node.destroy_node()
    zros.shutdown()
'''


@pytest.fixture
def probe(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A package `probe` (node `report`, `param/report.yaml`) on ZROS_NODE_PATH; returns its folder."""
    package = tmp_path / 'pkgs' / 'probe'
    (package / 'param').mkdir(parents=True)
    (package / 'report.py').write_text(REPORT_NODE)
    (package / 'param' / 'report.yaml').write_text('/**:\n  ros__parameters:\n    from_file: 7\n    rate: 1\n')
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path / 'pkgs'))
    return package


def reports(output: str) -> dict[str, dict]:
    """The probe reports in a launch's output, by fully qualified node name."""
    found = {}
    for line in output.splitlines():
        if 'REPORT ' in line:
            data = json.loads(line.split('REPORT ', 1)[1])
            found[data['fqn']] = data
    return found


def launch(*args: str, timeout: float = 60.0):
    return run_cli('launch', *map(str, args), timeout=timeout)


# -- one model, three front ends ---------------------------------------------------------------


def test_print_and_show_args_of_a_python_file_through_the_cli(tmp_path: Path):
    printed = launch(REPO / 'configs' / 'talker_listener.launch.py', 'topic:=news', '--print', '--log-dir', tmp_path)
    assert printed.returncode == 0, printed
    assert '-r chatter:=news' in printed.stdout and 'process [listener-2]' in printed.stdout
    shown = launch(REPO / 'configs' / 'talker_listener.launch.py', '--show-args')
    assert "'topic':" in shown.stdout and "(default: 'chatter')" in shown.stdout, shown


# -- every construct, in real runs ---------------------------------------------------------------
NODES_LAUNCH = '''
import os
import sys

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import (DeclareLaunchArgument, EmitEvent, ExecuteProcess, GroupAction,
                                 IncludeLaunchDescription, LogInfo, OpaqueFunction, RegisterEventHandler,
                                 SetEnvironmentVariable, TimerAction)
from zros.launch.conditions import IfCondition, LaunchConfigurationEquals, UnlessCondition
from zros.launch.event_handlers import OnProcessExit, OnProcessStart
from zros.launch.events import Shutdown
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource, YAMLLaunchDescriptionSource
from zros.launch.substitutions import (Command, EnvironmentVariable, LaunchConfiguration, PathJoinSubstitution,
                                       PythonExpression, TextSubstitution, ThisLaunchFileDir)
from zros.launch_ros.actions import Node, PushRosNamespace, SetParameter, SetRemap
from zros.launch_ros.parameter_descriptions import ParameterValue
from zros.launch_ros.substitutions import FindPackageShare


def say_mode(context, prefix):
    return [LogInfo(msg=prefix + LaunchConfiguration('mode').perform(context))]


def generate_launch_description():
    mode = LaunchConfiguration('mode')
    report = Node(
        package='probe', executable='report', name='reporter', namespace='inner', output='screen',
        arguments=['--flag', 'two words'],
        parameters=[PathJoinSubstitution([FindPackageShare('probe'), 'param', 'report.yaml']),
                    {'rate': PythonExpression([LaunchConfiguration('base'), ' * 2']),
                     'text': ParameterValue(Command(['echo ', TextSubstitution(text='42')]), value_type=str),
                     'mode_text': mode,
                     'home': EnvironmentVariable('PROBE_ENV', default_value='unset'),
                     'nested': {'deep': True}}],
        remappings=[('chatter', 'talk')])
    sleeper = ExecuteProcess(cmd=[sys.executable, '-c', 'import time; time.sleep(60)'], name='sleeper')
    return LaunchDescription([
        DeclareLaunchArgument('mode', default_value='fast', choices=['fast', 'slow']),
        DeclareLaunchArgument('base', default_value='5'),
        SetEnvironmentVariable('PROBE_ENV', 'from-launch'),
        GroupAction([
            PushRosNamespace('robot'),
            SetRemap('/unused', '/other'),
            SetParameter('scope_level', 3),
            TimerAction(period=0.3, actions=[report]),
        ]),
        Node(package='probe', executable='report', name='never', condition=UnlessCondition('true')),
        Node(package='probe', executable='report', name='slow_only', condition=LaunchConfigurationEquals('mode', 'slow')),
        LogInfo(msg='fast mode', condition=IfCondition(PythonExpression(["'", mode, "' == 'fast'"]))),
        OpaqueFunction(function=say_mode, args=['opaque saw mode=']),
        IncludeLaunchDescription(YAMLLaunchDescriptionSource(os.path.join(os.path.dirname(__file__), 'mid.launch.yaml')),
                                 launch_arguments={'who': mode}.items()),
        IncludeLaunchDescription(PythonLaunchDescriptionSource([ThisLaunchFileDir(), '/leaf.launch.py']),
                                 launch_arguments=[('depth', '1')]),
        sleeper,
        RegisterEventHandler(OnProcessStart(target_action=sleeper, on_start=[LogInfo(msg='sleeper started')])),
        RegisterEventHandler(OnProcessExit(
            target_action=report,
            on_exit=lambda event, context: [LogInfo(msg=f'report exited with {event.returncode}'),
                                            EmitEvent(event=Shutdown(reason='the report is in'))])),
    ])
'''

MID_YAML = '''
launch:
- arg: {name: who}
- log: {message: 'yaml include got $(var who)'}
- include:
    file: leaf.launch.py
    arg: [{name: depth, value: '2'}]
'''

LEAF_PY = '''
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, LogInfo
from zros.launch.substitutions import LaunchConfiguration, ThisLaunchFileDir


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('depth'),
        LogInfo(msg=['python leaf at depth ', LaunchConfiguration('depth')]),
    ])
'''


def test_a_python_launch_runs_every_construct(probe: Path, write, tmp_path: Path):
    main = write('main.launch.py', NODES_LAUNCH)
    write('mid.launch.yaml', MID_YAML)
    write('leaf.launch.py', LEAF_PY)
    started = time.monotonic()
    result = launch(main, '--log-dir', tmp_path / 'log', 'base:=21')
    assert result.returncode == 0, result
    assert time.monotonic() - started < 40, result
    out = result.stdout
    report = reports(out)['/robot/inner/reporter']
    # a command's output keeps its newline, as launch's Command does; a str-typed value keeps it too
    assert report['params'] == {'from_file': 7, 'rate': 42, 'text': '42\n', 'mode_text': 'fast', 'home': 'from-launch',
                                'nested.deep': True, 'scope_level': 3, 'start_type_description_service': True,
                                'use_sim_time': False}
    assert report['chatter'] == '/robot/inner/talk'
    assert report['unused'] == '/other'                              # SetRemap, for the whole group
    assert report['args'] == ['--flag', 'two words']
    assert report['env'] == 'from-launch'
    assert set(reports(out)) == {'/robot/inner/reporter'}            # the conditions held the others back
    for line in ('[INFO] [launch.user]: fast mode', '[INFO] [launch.user]: opaque saw mode=fast',
                 '[INFO] [launch.user]: yaml include got fast', '[INFO] [launch.user]: python leaf at depth 2',
                 '[INFO] [launch.user]: python leaf at depth 1',
                 '[INFO] [launch.user]: sleeper started', '[INFO] [launch.user]: report exited with 0',
                 'shutting down: the report is in'):
        assert line in out, (line, result)
    assert out.index('sleeper started') < out.index('report exited with 0') < out.index('shutting down')
    assert re.search(r"\[INFO\] \[sleeper-\d+\]: sending signal 'SIGINT'", out), result


def test_respawn_and_process_exit_handlers(probe: Path, write, tmp_path: Path):
    path = write('respawn.launch.py', '''
        import sys
        from zros.launch import LaunchDescription
        from zros.launch.actions import ExecuteProcess, LogInfo, RegisterEventHandler
        from zros.launch.event_handlers import OnProcessExit
        from zros.launch_ros.actions import Node


        def generate_launch_description():
            flaky = ExecuteProcess(cmd=[sys.executable, '-c', 'print("flaky ran"); raise SystemExit(3)'],
                                   name='flaky', output='screen', respawn=True, respawn_max_retries=1)
            return LaunchDescription([
                flaky,
                RegisterEventHandler(OnProcessExit(target_action=flaky, on_exit=[LogInfo(msg='flaky exited')])),
                Node(package='probe', executable='report', output='screen', respawn=True, respawn_max_retries=1),
            ])
        ''')
    result = launch(path, '--log-dir', tmp_path / 'log')
    assert result.returncode == 0, result
    assert result.stdout.count('[report-2] REPORT ') == 2, result
    assert result.stdout.count('[flaky-1] flaky ran') == 2, result
    assert result.stdout.count('[launch.user]: flaky exited') == 2, result
    assert result.stdout.count('exit code 3') == 2, result


def test_package_launch_file_on_the_node_path(probe: Path, tmp_path: Path):
    """`zros launch PKG FILE` finds `launch/FILE` in a package on ZROS_NODE_PATH."""
    (probe / 'launch').mkdir()
    (probe / 'launch' / 'report.launch.py').write_text(textwrap.dedent('''
        from zros.launch import LaunchDescription
        from zros.launch_ros.actions import Node

        def generate_launch_description():
            return LaunchDescription([Node(package='probe', executable='report', output='screen')])
        '''))
    result = launch('probe', 'report.launch.py', '--log-dir', tmp_path / 'log')
    assert result.returncode == 0, result
    assert '/report' in reports(result.stdout), result


# -- the plan, in process ---------------------------------------------------------------------


# -- errors: one line, file and line, at load time ---------------------------------------------------
@pytest.mark.parametrize('body, fragments', [
    ('from zros.launch.actions import OpaqueCoroutine\n',
     [':1: zros.launch.actions has no OpaqueCoroutine; supported: AppendEnvironmentVariable,', 'TimerAction']),
    ('import launch\nfrom rosbag2_py import SequentialReader\n', [":2: no module named 'rosbag2_py' (a ROS library zros does not provide: no zros.rosbag2_py)"]),
    ('from my_missing_msgs.msg import Thing\n', [":1: no module named 'my_missing_msgs' (no interface package 'my_missing_msgs' here"]),
    ('import my_missing_helpers\n', [":1: no module named 'my_missing_helpers' (not installed in this Python environment)"]),
    ('import zros.launch_ros.actions\n\ndef generate_launch_description():\n'
     '    return zros.launch_ros.actions.NoSuchAction("x")\n',
     [':4: zros.launch_ros.actions has no NoSuchAction; supported:', 'Node']),
    ('from zros.launch.event_handlers import event_named\n',
     [':1: zros.launch.event_handlers has no event_named; supported:', 'OnProcessIO']),
    ('from zros.launch import LaunchDescription\nfrom zros.launch_ros.actions import Node\n\n'
     'def generate_launch_description():\n'
     '    return LaunchDescription([Node(package="demo_nodes", executable="talker", colour="red")])\n',
     [":5: Node: colour: Node takes no argument 'colour'"]),
    ('from zros.launch import LaunchDescription\nfrom zros.launch_ros.actions import Node\n\n'
     'def generate_launch_description():\n    return LaunchDescription([Node(package="demo_nodes")])\n',
     [":5: TypeError: Node.__init__() missing 1 required keyword-only argument: 'executable'"]),
    ('def generate_launch_description():\n    return 1 / 0\n', [':2: ZeroDivisionError: division by zero']),
    ("import os\n\nMODEL = os.environ['ZROS_TEST_UNSET_MODEL']\n",
     [":3: KeyError: environment variable 'ZROS_TEST_UNSET_MODEL' is not set (export ZROS_TEST_UNSET_MODEL=...)"]),
    ('def generate_launch_description(:\n', [':1: invalid Python:']),
    ('x = 1\n', [': no generate_launch_description() function']),
    ('def generate_launch_description():\n    return [1]\n', ['returned list, not a LaunchDescription']),
    ('from zros.launch import LaunchDescription\nfrom zros.launch_ros.actions import Node\n\n'
     'def generate_launch_description():\n    return LaunchDescription([Node(package="demo_nodes", executable="talkr")])\n',
     [":5: Node: executable: no executable 'talkr' in package 'demo_nodes'"]),
    ('from zros.launch import LaunchDescription\nfrom zros.launch.actions import LogInfo\n'
     'from zros.launch.conditions import IfCondition\n\ndef generate_launch_description():\n'
     '    return LaunchDescription([LogInfo(msg="x", condition=IfCondition("maybe"))])\n',
     [":6: IfCondition: 'maybe' is not a boolean"]),
    ('from zros.launch import LaunchDescription\nfrom zros.launch.actions import LogInfo\n'
     'from zros.launch.substitutions import LaunchConfiguration\n\ndef generate_launch_description():\n'
     '    return LaunchDescription([LogInfo(msg=LaunchConfiguration("nope"))])\n',
     [":6: LogInfo: msg: launch configuration 'nope' is not set"]),
    ('from zros.launch import LaunchDescription\nfrom zros.launch.actions import OpaqueFunction\n\n'
     'def boom(context):\n    raise RuntimeError("bad idea")\n\ndef generate_launch_description():\n'
     '    return LaunchDescription([OpaqueFunction(function=boom)])\n',
     [':5: OpaqueFunction: boom() raised RuntimeError: bad idea']),
    ('from zros.launch import LaunchDescription\n\ndef generate_launch_description():\n'
     '    return LaunchDescription(["not an action"])\n',
     [':4: LaunchDescription: expected a launch action, got str']),
])
def test_bad_python_launch_files_fail_in_one_line(write, tmp_path: Path, body: str, fragments: list[str]):
    path = write('bad.launch.py', body)
    result = launch(path, '--print', '--log-dir', tmp_path / 'log')
    line = assert_clean_failure(result, str(path))
    for fragment in fragments:
        assert fragment in line, (fragment, line)


UPSTREAM_SHAPED = '''
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
import launch.action
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.conditions import IfCondition
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    assert issubclass(DeclareLaunchArgument, launch.action.Action)
    return LaunchDescription([
        DeclareLaunchArgument('talk', default_value='true'),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(
            get_package_share_directory('demo_nodes'), 'launch', 'talker_listener.launch.py'))),
        Node(package='demo_nodes', executable='talker', name='extra_talker',
             condition=IfCondition(LaunchConfiguration('talk'))),
    ])
'''


def test_a_launch_file_as_ros_writes_it_runs_unchanged(write, tmp_path: Path):
    """ROS's module names, an include through PythonLaunchDescriptionSource and a condition:
    the classes are zros's own whichever name imported them."""
    path = write('upstream.launch.py', UPSTREAM_SHAPED)
    result = launch(path, '--print', '--log-dir', tmp_path / 'log')
    assert result.returncode == 0, result
    assert 'node: /extra_talker' in result.stdout and 'node: /talker' in result.stdout, result.stdout
    assert 'node: /extra_talker' not in launch(path, 'talk:=false', '--print', '--log-dir', tmp_path / 'log').stdout


def test_binary_launch_files_fail_in_one_line(tmp_path: Path):
    binary = tmp_path / 'blob.launch.py'
    binary.write_bytes(bytes(range(256)) * 4)
    assert_clean_failure(launch(binary), f'{binary}: not a launch file: binary data, not UTF-8 text')
    yaml_binary = tmp_path / 'blob.launch.yaml'
    yaml_binary.write_bytes(b'\x00\xff\xfe' * 100)
    assert_clean_failure(launch(yaml_binary), 'not a launch file: binary data')
    xml_binary = tmp_path / 'blob.launch.xml'
    xml_binary.write_bytes(b'\x00\xff\xfe' * 100)
    assert_clean_failure(launch(xml_binary), 'not a launch file: binary data')


def test_a_container_started_as_a_node_is_an_empty_node_of_its_name(write, tmp_path: Path, domain: int):
    """Nav2's bringup starts `rclcpp_components component_container_isolated` as a Node and loads
    its servers into it; zros starts each component as a process and the container as an empty
    node, so `node list` shows it as ROS's does."""
    path = write('container.launch.py', '''
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([Node(package='rclcpp_components', executable='component_container_isolated',
                                   name='nav2_container', output='screen')])
''')
    plan = launch(path, '--print', '--log-dir', tmp_path / 'log')
    assert plan.returncode == 0 and 'node: /nav2_container' in plan.stdout, plan
    import subprocess
    from zros.testing import wait_until
    out = tmp_path / 'container.out'
    with open(out, 'wb') as sink:
        process = subprocess.Popen([sys.executable, '-m', 'zros', 'launch', str(path), '--log-dir', str(tmp_path / 'run')],
                                   stdout=sink, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        wait_until(lambda: '/nav2_container' in run_cli('node', 'list').stdout, 30, message='the container node')
        # its one line comes just after the node joins the graph: Ctrl-C only once it is out
        wait_until(lambda: 'this container holds none' in out.read_text(errors='replace'), 30,
                   message=lambda: out.read_text(errors='replace'))
    finally:
        os.killpg(process.pid, signal.SIGINT)
        process.wait(timeout=15)
    output = out.read_text(errors='replace')
    assert 'this container holds none' in output and 'Traceback' not in output, output
