"""The parameters an rclpy node has and the Node parameter API rclpy's own tests use."""
from __future__ import annotations

import pytest

from zros.exceptions import ParameterImmutableException
from zros.node import Node
from zros.parameter import Parameter
from zros.type_description_service import START_TYPE_DESCRIPTION_SERVICE_PARAM


def test_every_node_declares_the_read_only_type_description_switch(context):
    node = Node('type_description_user', context=context)
    assert node.get_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM).value is True
    assert node.describe_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM).read_only
    result, = node.set_parameters([Parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM, value=False)])
    assert not result.successful
    with pytest.raises(ParameterImmutableException):
        node.undeclare_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM)
    node.destroy_node()


def test_list_parameters_counts_depth_below_each_prefix(context):
    node = Node('lister', context=context)
    node.declare_parameters('', [('arm.joint.kp', 1.0), ('arm.joint.ki', 0.1), ('arm.speed', 2.0),
                                 ('base.speed', 1.0)])
    everything = node.list_parameters([], 0)
    assert {'arm.joint.kp', 'arm.speed', 'base.speed', 'use_sim_time'} <= set(everything.names)
    assert set(everything.prefixes) == {'arm.joint', 'arm', 'base'}
    top = node.list_parameters([], 1)
    assert 'use_sim_time' in top.names and not any('.' in n for n in top.names)
    under_arm = node.list_parameters(['arm'], 1)   # one level below 'arm', not below the root
    assert under_arm.names == ['arm.speed'] and under_arm.prefixes == ['arm']
    assert sorted(node.list_parameters(['arm'], 0).names) == ['arm.joint.ki', 'arm.joint.kp', 'arm.speed']
    with pytest.raises(ValueError):
        node.list_parameters([], -1)
    with pytest.raises(TypeError):
        node.list_parameters('arm', 0)
    node.destroy_node()


def test_set_descriptor_keeps_name_and_value_type(context):
    from interfaces.rcl_interfaces.msg import IntegerRange, ParameterDescriptor, ParameterType, ParameterValue
    from zros.exceptions import InvalidParameterValueException, ParameterNotDeclaredException
    node = Node('describer', context=context)
    with pytest.raises(ParameterNotDeclaredException):
        node.set_descriptor('gain', ParameterDescriptor())
    node.declare_parameter('gain', 4)
    value = node.set_descriptor('gain', ParameterDescriptor(
        name='ignored', type=ParameterType.PARAMETER_STRING, dynamic_typing=True,
        integer_range=[IntegerRange(from_value=0, to_value=10, step=1)]))
    assert value.integer_value == 4
    described = node.describe_parameter('gain')
    assert (described.name, described.type) == ('gain', ParameterType.PARAMETER_INTEGER)
    narrow = ParameterDescriptor(integer_range=[IntegerRange(from_value=0, to_value=2, step=1)])
    with pytest.raises(InvalidParameterValueException):
        node.set_descriptor('gain', narrow)   # 4 is out of range and there is no alternative
    value = node.set_descriptor('gain', narrow, ParameterValue(type=ParameterType.PARAMETER_INTEGER,
                                                                integer_value=1))
    assert value.integer_value == 1 and node.get_parameter('gain').value == 1
    node.set_descriptor('gain', ParameterDescriptor(read_only=True))
    with pytest.raises(ParameterImmutableException):
        node.set_descriptor('gain', ParameterDescriptor())
    node.destroy_node()


def test_undeclared_parameters_are_described_blank(context):
    node = Node('lenient', context=context, allow_undeclared_parameters=True)
    assert node.describe_parameter('anything').name == ''
    node.destroy_node()


def test_declaring_follows_rclpys_typing_rules(context):
    from interfaces.rcl_interfaces.msg import ParameterDescriptor, ParameterType, ParameterValue
    from zros.exceptions import InvalidParameterException, ParameterAlreadyDeclaredException
    node = Node('declarer', context=context)
    with pytest.warns(UserWarning, match='by its name alone'):
        assert node.declare_parameter('loose').type_ == Parameter.Type.NOT_SET
    assert node.describe_parameter('loose').dynamic_typing
    with pytest.raises(ValueError):
        node.declare_parameter('typeless', None, ParameterDescriptor())   # static, but no type
    with pytest.raises(ValueError):
        node.declare_parameter('nothing', Parameter.Type.NOT_SET)
    with pytest.raises(ValueError):
        node.declare_parameter('both', Parameter.Type.DOUBLE, ParameterDescriptor(dynamic_typing=True))
    from_msg = node.declare_parameter('from_msg', ParameterValue(type=ParameterType.PARAMETER_STRING,
                                                                 string_value='hi'))
    assert from_msg.value == 'hi'
    with pytest.raises(ParameterAlreadyDeclaredException):
        node.declare_parameters('', [('fresh', 1), ('from_msg', 'again')])
    assert not node.has_parameter('fresh')   # nothing is declared when one name is taken
    with pytest.raises(InvalidParameterException):
        node.declare_parameters('', [('fresh', 1), ('', 2)])
    assert not node.has_parameter('fresh')
    with pytest.raises(TypeError):
        node.declare_parameters('', [(1, 'not a name')])
    node.destroy_node()


def test_setting_undeclared_or_unsetting_static_parameters(context):
    from zros.exceptions import ParameterNotDeclaredException
    node = Node('setter', context=context)
    node.declare_parameter('first', 1)
    node.declare_parameter('counted', Parameter.Type.INTEGER)
    assert node.get_parameter_or('counted', Parameter('fallback', value=5)).value == 5   # unset
    with pytest.raises(ParameterNotDeclaredException):
        node.set_parameters([Parameter('first', value=2), Parameter('missing', value=3)])
    assert node.get_parameter('first').value == 2   # set one by one: the first went through
    result, = node.set_parameters([Parameter('first', Parameter.Type.NOT_SET)])
    assert not result.successful and result.reason == 'Static parameter cannot be undeclared'

    def add_undeclared(parameters):
        return parameters + [Parameter('sneaked', value=1)]
    node.add_pre_set_parameters_callback(add_undeclared)
    with pytest.raises(ParameterNotDeclaredException):   # checked after the pre-set callbacks
        node.set_parameters([Parameter('first', value=4)])
    assert node.get_parameter('first').value == 2
    node.destroy_node()


def test_only_parameters_can_be_set(context):
    node = Node('typed_setter', context=context)
    with pytest.raises(TypeError):
        node.set_parameters([42])
    with pytest.raises(TypeError):
        node.set_parameters_atomically(['use_sim_time'])
    node.destroy_node()


def test_the_executor_property_takes_any_executor_like_object(context):
    class Recorder:
        def __init__(self):
            self.calls = []

        def add_node(self, node):
            self.calls.append('add')
            return True

        def remove_node(self, node):
            self.calls.append('remove')

    node = Node('moved', context=context)
    first, second = Recorder(), Recorder()
    node.executor = first
    assert node.executor is first
    node.executor = second
    assert node.executor is second and first.calls == ['add', 'remove'] and second.calls == ['add']
    node.executor = None
    assert node.executor is None and second.calls == ['add', 'remove']
    node.destroy_node()


def test_a_file_after_a_value_on_the_command_line_wins_as_rcl_applies_them(context, tmp_path):
    params = tmp_path / 'later.yaml'
    params.write_text('/ordered:\n  ros__parameters: {first: from_file, second: from_file}\n')
    node = Node('ordered', context=context,
                cli_args=['--ros-args', '-p', 'first:=from_cli', '--params-file', str(params), '-p', 'second:=cli'])
    assert node.declare_parameter('first', '').value == 'from_file'
    assert node.declare_parameter('second', '').value == 'cli'
    node.destroy_node()


def test_declaring_checks_the_types_of_name_and_descriptor(context):
    from interfaces.rcl_interfaces.msg import ParameterValue
    from zros.exceptions import InvalidParameterException
    node = Node('declarer', context=context)
    with pytest.raises(TypeError):
        node.declare_parameter(1, 'a name must be a str')
    with pytest.raises(TypeError):
        node.declare_parameter('bad_descriptor', 1, ParameterValue())
    with pytest.raises(InvalidParameterException):
        node.declare_parameter('', 1)
    node.destroy_node()


def test_each_stage_of_set_parameters_callbacks_is_visible_and_removed_on_its_own(context):
    node = Node('staged', context=context)

    def either(parameters):
        return parameters
    node.add_pre_set_parameters_callback(either)
    node.add_post_set_parameters_callback(either)
    assert node._pre_set_parameters_callbacks[0] is either and node._post_set_parameters_callbacks[0] is either
    node.remove_post_set_parameters_callback(either)   # the pre-set registration stays
    assert either in node._pre_set_parameters_callbacks and either not in node._post_set_parameters_callbacks
    with pytest.raises(ValueError):
        node.remove_on_set_parameters_callback(either)
    node.add_pre_set_parameters_callback(lambda parameters: [])
    result, = node.set_parameters([Parameter('use_sim_time', value=False)])
    assert result.reason.endswith('modifying the original parameters list.')
    node.destroy_node()


def test_names_given_to_graph_queries_are_checked_as_rclpy_checks_them(context):
    from interfaces.std_msgs.msg import String
    from interfaces.std_srvs.srv import Trigger
    from zros.errors import InvalidServiceNameException
    node = Node('counter', namespace='/ns', context=context, cli_args=['--ros-args', '-r', 'chatter:=renamed'])
    node.create_publisher(String, 'chatter', 1)   # remapped to /ns/renamed
    assert node.count_publishers('renamed') == 1 and node.count_publishers('chatter') == 0   # expanded only
    with pytest.raises(TypeError):
        node.count_subscribers(1)
    with pytest.raises(ValueError, match='is invalid'):
        node.count_services('42')
    with pytest.raises(InvalidServiceNameException, match='must not contain characters'):
        node.create_client(Trigger, 'get/parameters?')
    with pytest.raises(TypeError, match='Expected QoSProfile or int'):
        node.create_publisher(String, 'chatter', 'deep')
    node.destroy_node()


def test_get_parameters_answers_nothing_when_one_name_has_no_value(context):
    from zros.executors import SingleThreadedExecutor
    from zros.parameter_client import AsyncParameterClient
    server = Node('holder', context=context)
    server.declare_parameter('typed_only', Parameter.Type.STRING)
    server.declare_parameter('set', 'yes')
    asker = Node('asker', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(server)
    executor.add_node(asker)
    client = AsyncParameterClient(asker, 'holder')
    assert client.wait_for_services(timeout_sec=10)

    def answer(future):
        executor.spin_until_future_complete(future, timeout_sec=10)
        return future.result()
    assert [v.string_value for v in answer(client.get_parameters(['set'])).values] == ['yes']
    assert answer(client.get_parameters(['set', 'typed_only'])).values == []   # declared, no value yet
    assert answer(client.get_parameters(['set', 'undeclared'])).values == []
    assert answer(client.describe_parameters(['typed_only'])).descriptors[0].type == Parameter.Type.STRING
    executor.shutdown()
    server.destroy_node()
    asker.destroy_node()
