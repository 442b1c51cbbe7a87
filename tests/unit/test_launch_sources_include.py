"""launch's description sources and IncludeLaunchDescription seen from Python: a source holding
a description built in Python, a Python launch file read on demand, what an include returns
when it is visited, and the required-argument check; no process is started."""
from __future__ import annotations

import pytest

from zros.launch import LaunchContext, LaunchDescription, LaunchDescriptionSource
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription, SetLaunchConfiguration
from zros.launch.errors import LaunchError, LaunchFileError
from zros.launch.invalid_launch_file_error import InvalidLaunchFileError
from zros.launch.launch_description_sources import (InvalidPythonLaunchFileError, PythonLaunchDescriptionSource,
                                                    get_launch_description_from_python_launch_file,
                                                    load_python_launch_file_as_module)

LAUNCH_PY = 'from launch import LaunchDescription\n\ndef generate_launch_description():\n    return LaunchDescription()\n'


def test_a_source_of_a_python_built_description():
    description = LaunchDescription()
    source = LaunchDescriptionSource(description, 'here', 'made by hand')
    assert (source.location, source.method) == ('here', 'made by hand')
    assert source.get_launch_description(LaunchContext()) is description
    with pytest.raises(LaunchError):   # a RuntimeError, as launch's
        LaunchDescriptionSource().get_launch_description(LaunchContext())


def test_python_launch_files_read_on_demand(tmp_path):
    good, plain = tmp_path / 'a.launch.py', tmp_path / 'plain.py'
    good.write_text(LAUNCH_PY)
    plain.write_text('VALUE = 3\n')
    source = PythonLaunchDescriptionSource(str(good))
    assert 'python launch file' in source.method
    assert isinstance(source.get_launch_description(LaunchContext()), LaunchDescription)
    assert source.location == str(good)
    assert load_python_launch_file_as_module(str(plain)).VALUE == 3
    with pytest.raises(InvalidPythonLaunchFileError):
        get_launch_description_from_python_launch_file(str(plain))
    with pytest.raises(FileNotFoundError):
        get_launch_description_from_python_launch_file(str(tmp_path / 'missing.py'))


def test_include_returns_its_arguments_then_the_description():
    description = LaunchDescription([DeclareLaunchArgument('who')])
    include = IncludeLaunchDescription(LaunchDescriptionSource(description, '<script>'),
                                       launch_arguments={'who': 'me'}.items())
    context = LaunchContext()
    first, second = include.visit(context)
    assert isinstance(first, SetLaunchConfiguration) and second is description
    assert context.locals.current_launch_file_directory == '<script>'
    assert include.describe_sub_entities() == [description]


def test_include_must_pass_required_arguments_itself():
    inner = LaunchDescription([DeclareLaunchArgument('who', description='whom to greet'),
                               DeclareLaunchArgument('loud', default_value='false')])
    context = LaunchContext(launch_arguments={'who': 'set elsewhere'})
    with pytest.raises(LaunchFileError, match=r"missing required argument 'who' \(description: 'whom to greet'\), "
                                              r'given: \[other\]'):
        IncludeLaunchDescription(LaunchDescriptionSource(inner), launch_arguments=[('other', 'x')]).visit(context)
    # one declared deeper may be passed by the include in between
    middle = LaunchDescription([IncludeLaunchDescription(LaunchDescriptionSource(inner),
                                                         launch_arguments=[('who', 'x')])])
    IncludeLaunchDescription(LaunchDescriptionSource(middle)).visit(LaunchContext())


def test_a_file_of_no_known_format_is_tried_as_yaml_and_xml(tmp_path):
    from zros.launch.files import load_launch_file
    xml = tmp_path / 'demo.launchfile'
    xml.write_text('<launch><let name="x" value="1"/></launch>\n')
    assert len(load_launch_file(str(xml))) == 1
    xml.write_text('<launch><let name="x"\n')
    with pytest.raises(InvalidLaunchFileError) as failure:
        load_launch_file(str(xml))
    assert 'format [.launchfile: yaml, xml]' in str(failure.value) and 'LaunchFileError' in str(failure.value)
    assert 'KeyError: ' in str(InvalidLaunchFileError('.py', likely_errors=[KeyError('k')]))
