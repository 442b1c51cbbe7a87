"""What foxglove_bridge advertises, without a server: ros2msg schemas, names, whitelists."""
from __future__ import annotations

import pytest

from zros.bridges.foxglove_schema import (allowed, channel_schema, compile_whitelist, full_type_name, is_hidden,
                                          parameter_name, service_schemas, split_parameter_name)


def test_a_string_topic_is_advertised_with_its_msg_text_as_a_ros2msg_schema():
    schema = channel_schema('std_msgs/msg/String')
    assert (schema.name, schema.encoding) == ('std_msgs/msg/String', 'ros2msg')
    lines = [line for line in schema.data.decode().splitlines() if line and not line.startswith('#')]
    assert lines == ['string data']


def test_nested_types_follow_the_root_once_each_in_rosbag2s_concatenated_form():
    text = channel_schema('tf2_msgs/msg/TFMessage').data.decode()
    blocks = text.split('=' * 80 + '\n')
    assert 'geometry_msgs/TransformStamped[] transforms' in blocks[0]
    names = [block.splitlines()[0] for block in blocks[1:]]
    assert names == sorted(set(names), key=names.index)  # each dependency once
    for name in ('MSG: geometry_msgs/TransformStamped', 'MSG: std_msgs/Header', 'MSG: builtin_interfaces/Time',
                 'MSG: geometry_msgs/Transform', 'MSG: geometry_msgs/Vector3', 'MSG: geometry_msgs/Quaternion'):
        assert name in names


def test_the_schema_parses_back_into_the_same_types_with_rosbags():
    from rosbags.typesys import get_types_from_msg
    types = get_types_from_msg(channel_schema('sensor_msgs/msg/LaserScan').data.decode(), 'sensor_msgs/msg/LaserScan')
    assert {'sensor_msgs/msg/LaserScan', 'std_msgs/msg/Header', 'builtin_interfaces/msg/Time'} <= set(types)


def test_a_service_has_request_and_response_schemas_named_as_rosbag2_names_them():
    request, response = service_schemas('example_interfaces/srv/AddTwoInts')
    assert request.name == 'example_interfaces/srv/AddTwoInts_Request'
    assert response.name == 'example_interfaces/srv/AddTwoInts_Response'
    assert [line for line in request.data.decode().splitlines() if line and not line.startswith('#')] == \
        ['int64 a', 'int64 b']
    assert 'int64 sum' in response.data.decode()


def test_an_unknown_type_is_an_error_naming_it():
    from zros.errors import ZrosError
    with pytest.raises(ZrosError, match='no_such_pkg'):
        channel_schema('no_such_pkg/msg/Nothing')


@pytest.mark.parametrize('name, full', [('geometry_msgs/PoseStamped', 'geometry_msgs/msg/PoseStamped'),
                                        ('geometry_msgs/msg/PoseStamped', 'geometry_msgs/msg/PoseStamped'),
                                        ('/std_msgs/String', 'std_msgs/msg/String')])
def test_foxglove_panel_type_names_become_full_names(name, full):
    assert full_type_name(name) == full


def test_whitelists_match_whole_names_as_foxglove_bridges_regex_match():
    whitelist = compile_whitelist(['/scan', '/tf.*'])
    assert allowed('/scan', whitelist) and allowed('/tf_static', whitelist)
    assert not allowed('/scan_filtered', whitelist) and not allowed('/map', whitelist)
    assert allowed('/anything', compile_whitelist(['.*']))


def test_a_bad_whitelist_pattern_is_one_error_naming_it():
    with pytest.raises(ValueError, match=r"invalid whitelist pattern '\[oops'"):
        compile_whitelist(['[oops'])


def test_hidden_names_have_a_part_starting_with_underscore():
    assert is_hidden('/_private/x') and is_hidden('/a/_b')
    assert not is_hidden('/chatter') and not is_hidden('/a_b/c_')


def test_parameter_names_are_node_dot_parameter_and_split_back():
    assert parameter_name('/turtlesim', 'background_r') == '/turtlesim.background_r'
    assert split_parameter_name('/ns/node.qos.depth') == ('/ns/node', 'qos.depth')
    for bad in ('no_slash.p', '/node', '/node.', '/.p'):
        with pytest.raises(ValueError, match='is not'):
            split_parameter_name(bad)
