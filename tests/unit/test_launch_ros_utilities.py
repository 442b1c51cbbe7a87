"""zros.launch_ros.utilities (launch_ros.utilities): namespaces, remap rules and duplicate node
names, as launch_ros code uses them and as `zros launch` resolves nodes."""
from __future__ import annotations

import textwrap

import pytest

from zros.launch import resolve
from zros.launch.context import LaunchContext
from zros.launch.plan import LogMessage
from zros.launch.substitutions import LaunchConfiguration
from zros.launch.utilities import perform_substitutions
from zros.launch_ros.utilities import (add_node_name, get_node_name_count, make_namespace_absolute,
                                       normalize_remap_rule, normalize_remap_rules, prefix_namespace)


@pytest.mark.parametrize('base, ns, expected', [
    (None, None, None), ('robot', None, 'robot'), (None, 'scan', 'scan'), ('robot', 'scan', 'robot/scan'),
    ('/robot', 'scan/', '/robot/scan'), ('/robot', '/other', '/other'), ('/', 'scan', '/scan'), ('', 'scan', 'scan'),
    ('/', None, '/'), ('robot/', '', 'robot'),
])
def test_a_relative_namespace_goes_under_the_pushed_one(base, ns, expected):
    assert prefix_namespace(base, ns) == expected


def test_make_namespace_absolute():
    assert make_namespace_absolute('') == '/' and make_namespace_absolute('a/b') == '/a/b'
    assert make_namespace_absolute('/a') == '/a' and make_namespace_absolute(None) is None


def test_remap_rule_sides_are_substitutions():
    context = LaunchContext(launch_arguments={'robot': 'r2'})
    source, target = normalize_remap_rule(('scan', ['/', LaunchConfiguration('robot'), '/scan']))
    assert isinstance(source, tuple) and perform_substitutions(context, target) == '/r2/scan'
    assert [perform_substitutions(context, s) for s, _ in normalize_remap_rules([('a', 'b'), ('c', 'd')])] == ['a', 'c']
    for bad in (['a', 'b'], ('a',), ('a', 'b', 'c'), ('a', 1)):
        with pytest.raises(TypeError):
            normalize_remap_rule(bad)


def test_node_names_are_counted_per_context():
    context = LaunchContext()
    add_node_name(context, '/ns/a')
    add_node_name(context, '/ns/a')
    assert get_node_name_count(context, '/ns/a') == 2 and get_node_name_count(context, '/a') == 0
    assert get_node_name_count(context.snapshot(), '/ns/a') == 2  # a handler's context shares them


def test_zros_launch_warns_when_two_nodes_share_a_name(tmp_path):
    launch_file = tmp_path / 'dup.launch.yaml'
    launch_file.write_text(textwrap.dedent('''\
        launch:
        - node: {pkg: demo_nodes, exec: talker, name: talker, namespace: ns}
        - node: {pkg: demo_nodes, exec: talker, name: talker, namespace: /ns}
        - node: {pkg: demo_nodes, exec: listener}
        '''))
    plan = resolve(str(launch_file))
    warnings = [e.message for e in plan.effects if isinstance(e, LogMessage) and e.level == 'WARNING']
    assert warnings == ['there are now at least 2 nodes with the name /ns/talker created within this launch context']


# -- parameters -----------------------------------------------------------------------------------
def test_parameters_evaluate_to_files_and_one_dict_per_dict():
    from pathlib import Path

    from zros.launch.substitutions import TextSubstitution
    from zros.launch_ros.utilities import evaluate_parameters, normalize_parameters
    context = LaunchContext(launch_arguments={'rate': '10'})
    normalized = normalize_parameters([
        '/cfg/a.yaml',
        {'rate': LaunchConfiguration('rate'), 'limits': {'max': 2, 'names': ['x', 'y']}},
        {'gains': [[TextSubstitution(text='1.5')], 2.5], 'label': [TextSubstitution(text='ab'), 'c']},
    ])
    assert evaluate_parameters(context, normalized) == (
        Path('/cfg/a.yaml'),
        {'rate': 10, 'limits.max': 2, 'limits.names': ('x', 'y')},
        {'gains': (1.5, 2.5), 'label': 'abc'},
    )
    for bad in ({'a': 1}, 'file.yaml', [3]):
        with pytest.raises(TypeError):
            normalize_parameters(bad)


@pytest.mark.parametrize('value', [[True, 1], [[LaunchConfiguration('x')], 2]])
def test_a_list_parameter_must_have_one_type(value):
    from zros.launch.errors import LaunchFileError
    from zros.launch_ros.utilities import evaluate_parameters, normalize_parameters
    with pytest.raises(TypeError, match='Expected a non-empty sequence') as info:
        evaluate_parameters(LaunchContext(launch_arguments={'x': 'a'}), normalize_parameters([{'p': value}]))
    assert isinstance(info.value, LaunchFileError)   # zros launch reports it with file:line


@pytest.mark.parametrize('text', ['[]', '[1, a]', '[[1], [2]]'])
def test_a_substitution_must_give_a_typed_list(text):
    from zros.launch.substitutions import TextSubstitution
    from zros.launch_ros.utilities import evaluate_parameters, normalize_parameters
    with pytest.raises(TypeError, match='Expected a non-empty sequence'):
        evaluate_parameters(LaunchContext(), normalize_parameters([{'p': TextSubstitution(text=text)}]))


def test_text_yaml_cannot_type_stays_a_string():
    """zros differs from launch_ros here on purpose: a URDF read by $(file-content) works unwrapped."""
    from zros.launch.substitutions import TextSubstitution
    from zros.launch_ros.utilities import evaluate_parameters, normalize_parameters
    for text in ("{'a': 3}", 'a : b : c', '<robot name="r"><link name="a: b"/></robot>'):
        assert evaluate_parameters(LaunchContext(), normalize_parameters([{'p': TextSubstitution(text=text)}])) \
            == ({'p': text},)


def test_a_parameter_description_evaluates_to_its_name_and_value():
    from zros.launch.parameters import Parameter, ParameterFile
    from zros.launch_ros.utilities import evaluate_parameters, normalize_parameters
    normalized = normalize_parameters([Parameter('rate', LaunchConfiguration('r')), ParameterFile('/p.yaml')])
    assert evaluate_parameters(LaunchContext(launch_arguments={'r': '5'}), normalized)[0] == {'rate': 5}
