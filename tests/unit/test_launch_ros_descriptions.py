"""launch_ros's parameter descriptions as launch_ros code uses them: as given until evaluated,
then the evaluated value; a plain value of the wrong type is a TypeError up front; a file with
substitutions is evaluated into a temporary copy that `cleanup()` removes."""
from __future__ import annotations

from pathlib import Path
from typing import List

import pytest

from zros.launch import LaunchContext
from zros.launch.substitutions import LaunchConfiguration, TextSubstitution
from zros.launch_ros.descriptions import Parameter, ParameterFile, ParameterValue


def test_a_parameter_value_is_substitutions_until_evaluated():
    value = ParameterValue(TextSubstitution(text='[1, 2]'))
    assert [type(s) for s in value.value] == [TextSubstitution]
    assert value.evaluate(LaunchContext()) == [1, 2] and value.value == [1, 2]
    typed = ParameterValue(['[', LaunchConfiguration('n'), ']'], value_type=List[int])
    assert typed.evaluate(LaunchContext(launch_arguments={'n': '3, 4'})) == [3, 4]


def test_a_plain_value_of_another_type_is_refused_up_front():
    with pytest.raises(TypeError):
        ParameterValue('1', value_type=int)
    with pytest.raises(TypeError):
        Parameter('p', ['a', 1], value_type=List[str])
    assert ParameterValue([TextSubstitution(text='x')], value_type=List[str]).value_type == List[str]


def test_a_mixed_list_from_a_substitution_is_a_value_error():
    with pytest.raises(ValueError):
        ParameterValue(TextSubstitution(text='[1, asd]')).evaluate(LaunchContext())


def test_a_parameter_evaluates_to_its_name_and_value():
    parameter = Parameter(['rate', TextSubstitution(text='_hz')], TextSubstitution(text='10'))
    assert [type(s) for s in parameter.name] == [TextSubstitution, TextSubstitution]
    assert parameter.evaluate(LaunchContext()) == ('rate_hz', 10)
    assert (parameter.name, parameter.value) == ('rate_hz', 10)


def test_a_parameter_file_with_substitutions_is_evaluated_into_a_temporary_copy(tmp_path):
    path = tmp_path / 'p.yaml'
    path.write_text('/**:\n  ros__parameters:\n    robot: $(var robot)\n')
    description = ParameterFile(str(path), allow_substs=True)
    copy = description.evaluate(LaunchContext(launch_arguments={'robot': 'r2'}))
    assert copy != path and 'robot: r2' in copy.read_text() and description.param_file == copy
    description.cleanup()
    assert not copy.exists() and isinstance(description.param_file, list)


def test_a_parameter_file_without_substitutions_is_the_file_itself(tmp_path):
    path = tmp_path / 'p.yaml'
    path.write_text('/**:\n  ros__parameters: {a: 1}\n')
    description = ParameterFile(path)
    assert description.evaluate(LaunchContext()) == Path(path)
    description.cleanup()
    assert description.param_file == Path(path) and path.exists()
