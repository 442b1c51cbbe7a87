"""rclpy's rules for Parameter values and parameter files, as rclpy's own tests state them."""
from __future__ import annotations

import textwrap

import pytest

from interfaces.rcl_interfaces.msg import ParameterValue
from zros.arguments import parse_ros_args
from zros.parameter import (Parameter, ParameterFileError, load_parameter_file, parameter_dict_from_yaml_file,
                            parameter_value_to_python)


def test_a_value_of_the_wrong_type_is_a_value_error_and_an_unknown_type_a_type_error():
    with pytest.raises(ValueError):
        Parameter('p', Parameter.Type.BOOL_ARRAY, 42)
    with pytest.raises(ValueError):   # only None is NOT_SET
        Parameter('p', Parameter.Type.NOT_SET, 42)
    with pytest.raises(TypeError):
        Parameter('p', 'no such type', 'value')
    with pytest.raises(TypeError):   # nothing to infer a type from
        Parameter('p', value={'a': 'dict'})
    assert Parameter('p', Parameter.Type.NOT_SET).value is None


def test_equal_parameters_hash_alike_so_sets_of_them_compare():
    assert {Parameter('a', value=[1, 2]), Parameter('b', value='x')} == {Parameter('b', value='x'),
                                                                         Parameter('a', value=[1, 2])}
    assert hash(Parameter('a', value=1.0)) == hash(Parameter('a', Parameter.Type.DOUBLE, 1))


def test_an_unknown_parameter_value_type_is_a_runtime_error():
    with pytest.raises(RuntimeError, match='unexpected parameter type 42'):
        parameter_value_to_python(ParameterValue(type=42))


def test_a_missing_parameter_file_is_a_file_not_found_error_and_a_parameter_file_error(tmp_path):
    missing = str(tmp_path / 'missing.yaml')
    for read in (lambda: parameter_dict_from_yaml_file(missing), lambda: load_parameter_file(missing, '/n')):
        with pytest.raises(FileNotFoundError) as info:
            read()
        assert isinstance(info.value, ParameterFileError) and 'missing.yaml' in str(info.value)


def test_a_key_given_twice_in_a_parameter_file_merges_as_rcl_reads_it(tmp_path):
    path = tmp_path / 'twice.yaml'
    path.write_text(textwrap.dedent('''
        /**:
          ros__parameters: {everyone: 1}
        /**:
          robot:
            ros__parameters: {robot_anywhere: 2}
        ns:
          robot:
            ros__parameters: {in_ns: 3}
        ns:
          "*":
            ros__parameters: {any_in_ns: 4}
        '''))
    assert load_parameter_file(str(path), '/ns/robot') == {'everyone': 1, 'robot_anywhere': 2, 'in_ns': 3,
                                                           'any_in_ns': 4}


def test_a_node_key_is_read_from_the_root_with_or_without_its_slash(tmp_path):
    path = tmp_path / 'keys.yaml'
    path.write_text('robot:\n  ros__parameters: {bare: 1}\n"*":\n  ros__parameters: {star: 2}\n'
                    '/ns/*:\n  ros__parameters: {in_ns: 3}\n')
    assert load_parameter_file(str(path), '/robot') == {'bare': 1, 'star': 2}
    assert load_parameter_file(str(path), '/ns/robot') == {'in_ns': 3}


def test_parameter_values_and_files_keep_their_command_line_order():
    args = parse_ros_args(['prog', '--ros-args', '-p', 'a:=1', '--params-file', 'f.yaml', '-p', 'b:=2'])
    assert args.parameter_sources == [('a', '1'), 'f.yaml', ('b', '2')]
