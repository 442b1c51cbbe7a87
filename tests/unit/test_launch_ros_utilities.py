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
