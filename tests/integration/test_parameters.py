"""Parameters: declarations, typing rules, overrides, callbacks, remote access and the CLI."""
from __future__ import annotations

import pytest
import yaml

from conftest import wait_until

from zros.exceptions import (InvalidParameterValueException, ParameterAlreadyDeclaredException,
                             ParameterImmutableException, ParameterNotDeclaredException,
                             ParameterUninitializedException)
from zros.node import Node
from zros.parameter import Parameter

from interfaces.rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                           SetParametersResult)


def test_declare_get_set_with_ros_typing(context):
    node = Node('typed', context=context)
    assert node.declare_parameter('count', 3).value == 3
    assert node.get_parameter('count').type_ == Parameter.Type.INTEGER
    assert node.declare_parameters('ns', [('a', 1.5), ('b', 'text'), ('c', [1, 2])])[2].value == [1, 2]
    assert node.get_parameter('ns.b').value == 'text'
    assert set(node.get_parameters_by_prefix('ns')) == {'a', 'b', 'c'}
    result = node.set_parameters([Parameter('count', value='four')])[0]
    assert not result.successful and 'is of type {INTEGER}' in result.reason
    assert node.set_parameters([Parameter('count', value=4)])[0].successful
    assert node.get_parameter('count').value == 4
    with pytest.raises(ParameterAlreadyDeclaredException):
        node.declare_parameter('count', 1)
    with pytest.raises(ParameterNotDeclaredException):
        node.get_parameter('nope')
    with pytest.raises(ParameterNotDeclaredException):
        node.set_parameters([Parameter('nope', value=1)])
    assert node.get_parameter_or('nope', Parameter('nope', value=7)).value == 7
    assert node.has_parameter('use_sim_time') and node.get_parameter('use_sim_time').value is False


def test_dynamic_typing_read_only_and_uninitialized(context):
    node = Node('rules', context=context)
    node.declare_parameter('any', 1, ParameterDescriptor(dynamic_typing=True))
    assert node.set_parameters([Parameter('any', value='now a string')])[0].successful
    node.declare_parameter('fixed', 'x', ParameterDescriptor(read_only=True))
    result = node.set_parameters([Parameter('fixed', value='y')])[0]
    assert not result.successful and 'read-only' in result.reason
    with pytest.raises(ParameterImmutableException):
        node.undeclare_parameter('fixed')
    node.declare_parameter('later', Parameter.Type.DOUBLE)
    with pytest.raises(ParameterUninitializedException):
        node.get_parameter('later')
    node.undeclare_parameter('any')
    assert not node.has_parameter('any')


def test_ranges_and_steps(context):
    node = Node('ranged', context=context)
    node.declare_parameter('speed', 5, ParameterDescriptor(
        integer_range=[IntegerRange(from_value=0, to_value=10, step=5)]))
    node.declare_parameter('gain', 0.5, ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0, step=0.25)]))
    assert not node.set_parameters([Parameter('speed', value=11)])[0].successful
    assert 'out of range' in node.set_parameters([Parameter('speed', value=-1)])[0].reason
    assert 'step' in node.set_parameters([Parameter('speed', value=3)])[0].reason
    assert node.set_parameters([Parameter('speed', value=10)])[0].successful
    assert 'step' in node.set_parameters([Parameter('gain', value=0.3)])[0].reason
    assert node.set_parameters([Parameter('gain', value=0.75)])[0].successful
    with pytest.raises(InvalidParameterValueException):
        node.declare_parameter('bad', 20, ParameterDescriptor(integer_range=[IntegerRange(from_value=0, to_value=10)]))


def test_callbacks_pre_on_post(context):
    node = Node('callbacks', context=context)
    node.declare_parameter('level', 1)
    seen = []
    node.add_pre_set_parameters_callback(lambda params: [Parameter(p.name, value=p.value * 10) for p in params])
    node.add_on_set_parameters_callback(
        lambda params: SetParametersResult(successful=all(p.value < 100 for p in params), reason='too big'))
    node.add_post_set_parameters_callback(lambda params: seen.extend(p.value for p in params))
    assert node.set_parameters([Parameter('level', value=2)])[0].successful
    assert node.get_parameter('level').value == 20 and seen == [20]
    result = node.set_parameters([Parameter('level', value=50)])[0]
    assert not result.successful and result.reason == 'too big'
    assert node.get_parameter('level').value == 20
    atomic = node.set_parameters_atomically([Parameter('level', value=3)])
    assert atomic.successful and node.get_parameter('level').value == 30


def test_parameter_event_qos_overrides_as_rclcpp_nodes_declare_them(context):
    """rclcpp nodes (turtlesim) list four read-only qos_overrides for /parameter_events, rclpy
    nodes none; a start-up value sets the publisher's QoS."""
    names = [f'qos_overrides./parameter_events.publisher.{policy}'
             for policy in ('depth', 'durability', 'history', 'reliability')]
    plain = Node('like_rclpy', context=context)
    assert not any(plain.has_parameter(name) for name in names)
    like_cpp = Node('like_rclcpp', context=context, parameter_event_qos_overrides=True,
                    cli_args=['-p', 'qos_overrides./parameter_events.publisher.depth:=20'])
    assert [like_cpp.get_parameter(name).value for name in names] == [20, 'volatile', 'keep_last', 'reliable']
    assert all(like_cpp.describe_parameter(name).read_only for name in names)
    events = wait_until(lambda: [e for e in like_cpp.get_publishers_info_by_topic('/parameter_events')
                                 if e.node_name == 'like_rclcpp'], 5, message='the node\'s /parameter_events publisher')
    assert events[0].qos_profile.to_token() == 'R:V:L20'   # QoSProfile.to_token(): reliable, volatile, keep last 20
    refused = like_cpp.set_parameters([Parameter(names[0], value=5)])[0]
    assert not refused.successful and 'read-only' in refused.reason


def test_overrides_from_arguments_and_files_with_wildcards(tmp_path, context):
    params = tmp_path / 'params.yaml'
    params.write_text(yaml.safe_dump({
        '/**': {'ros__parameters': {'shared': 'everyone', 'speed': 1}},
        '/robot/driver': {'ros__parameters': {'speed': 2, 'pid': {'p': 0.5, 'i': 0.1}}},
        'other': {'ros__parameters': {'speed': 99}},
    }))
    node = Node('driver', namespace='/robot', context=context,
                cli_args=['--params-file', str(params), '-p', 'speed:=3', '-p', 'name:=zeta'])
    assert node.declare_parameter('speed', 0).value == 3          # -p wins over files
    assert node.declare_parameter('shared', '').value == 'everyone'
    assert node.declare_parameter('pid.p', 0.0).value == 0.5      # nested keys flatten with '.'
    assert node.declare_parameter('name', '').value == 'zeta'
    assert node.declare_parameter('ignored', 5, ignore_override=True).value == 5
    auto = Node('auto', context=context, cli_args=['-p', 'x:=1.5', '-p', 'flag:=true'],
                automatically_declare_parameters_from_overrides=True)
    assert auto.get_parameter('x').value == 1.5 and auto.get_parameter('flag').value is True
    loose = Node('loose', context=context, allow_undeclared_parameters=True)
    assert loose.set_parameters([Parameter('new_one', value=[1.0, 2.0])])[0].successful
    assert loose.get_parameter('new_one').value == [1.0, 2.0]


@pytest.fixture
def param_talker(spawn, tmp_path):
    params = tmp_path / 'talker.yaml'
    params.write_text(yaml.safe_dump({'/**': {'ros__parameters': {'timer_period': 0.2}},
                                      'param_talker': {'ros__parameters': {'published_text': 'From file'}}}))
    child = spawn.node('demo_nodes', 'param_talker', '--ros-args', '--params-file', str(params),
                       '-p', 'published_text:=Hi')
    child.wait_for_output("Publishing: 'Hi: 1'", timeout=15)
    return child


def test_param_cli_round_trip(param_talker, zros_cli, tmp_path):
    listed = zros_cli('param', 'list', '/param_talker')
    assert listed.returncode == 0, listed
    assert listed.stdout.splitlines()[0] == '/param_talker:'
    assert {'  published_text', '  timer_period', '  use_sim_time'} <= set(listed.stdout.splitlines())
    assert zros_cli('param', 'get', '/param_talker', 'published_text').stdout.strip() == 'String value is: Hi'
    assert zros_cli('param', 'get', '/param_talker', 'timer_period').stdout.strip() == 'Double value is: 0.2'
    assert zros_cli('param', 'set', '/param_talker', 'published_text', 'BME').stdout.strip() == 'Set parameter successful'
    param_talker.wait_for_output("Publishing: 'BME:", timeout=5)
    out_of_range = zros_cli('param', 'set', '/param_talker', 'timer_period', '20.0')
    assert out_of_range.returncode == 1
    assert out_of_range.stderr.strip().endswith('Setting parameter failed: Parameter timer_period out of range. Min: 0.1, Max: 10.0')
    rejected = zros_cli('param', 'set', '/param_talker', 'published_text', '" "')
    assert rejected.returncode == 1 and 'published_text must not be empty' in rejected.stderr
    described = zros_cli('param', 'describe', '/param_talker', 'timer_period').stdout
    assert 'Type: double' in described and 'Min value: 0.1' in described and 'Max value: 10.0' in described
    assert zros_cli('param', 'set', '/param_talker', 'extra', '42').returncode == 0
    assert zros_cli('param', 'get', '/param_talker', 'extra').stdout.strip() == 'Integer value is: 42'
    dump = zros_cli('param', 'dump', '/param_talker')
    document = yaml.safe_load(dump.stdout)
    assert document['/param_talker']['ros__parameters']['published_text'] == 'BME'
    assert document['/param_talker']['ros__parameters']['extra'] == 42
    assert zros_cli('param', 'delete', '/param_talker', 'extra').stdout.strip() == 'Deleted parameter successfully'
    assert zros_cli('param', 'get', '/param_talker', 'extra').returncode == 1
    dumped = tmp_path / 'p.yaml'
    document['/param_talker']['ros__parameters']['published_text'] = 'Loaded'
    dumped.write_text(yaml.safe_dump(document))
    loaded = zros_cli('param', 'load', '/param_talker', str(dumped))
    assert loaded.returncode == 0, loaded
    assert 'Set parameter published_text successful' in loaded.stdout
    assert 'Skipped read-only parameter start_type_description_service' in loaded.stdout
    assert zros_cli('param', 'get', '/param_talker', 'published_text').stdout.strip() == 'String value is: Loaded'
    assert zros_cli('param', 'get', '/param_talker', 'extra').stdout.strip() == 'Integer value is: 42'
    changed = zros_cli('param', 'set', '/param_talker', 'timer_period', '0.5')
    assert changed.returncode == 0
    param_talker.wait_for_output('timer_period is now 0.5 s', timeout=5)
    missing = zros_cli('param', 'get', '/nobody', 'x')
    assert missing.returncode == 1 and 'Node not found' in missing.stderr and 'Traceback' not in missing.stderr


def test_parameter_events_reach_a_subscriber(context, param_talker, zros_cli, spin_for):
    from zros.executors import SingleThreadedExecutor
    from interfaces.rcl_interfaces.msg import ParameterEvent
    node = Node('event_watcher', context=context)
    events = []
    node.create_subscription(ParameterEvent, '/parameter_events', events.append, 100)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    executor.spin_once(timeout_sec=0.3)
    assert zros_cli('param', 'set', '/param_talker', 'published_text', 'Evented').returncode == 0
    spin_for(executor, lambda: any(e.node == '/param_talker' and any(
        p.name == 'published_text' and p.value.string_value == 'Evented' for p in e.changed_parameters)
        for e in events), timeout=5)
