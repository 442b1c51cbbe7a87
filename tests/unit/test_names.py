"""zros.names: ROS 2 name validation, expansion and remapping (no network)."""
from __future__ import annotations

import pytest

from zros.arguments import RosArgsError, parse_ros_args, remove_ros_args
from zros.errors import InvalidNameError, ZrosError
from zros.names import (Remappings, expand_topic_name, fully_qualified_node_name, normalize_namespace,
                        validate_full_name, validate_namespace, validate_node_name)


# -- expansion ---------------------------------------------------------------------------------
@pytest.mark.parametrize('name, node, ns, expected', [
    ('chatter', 'talker', '/', '/chatter'),
    ('chatter', 'talker', '/robot', '/robot/chatter'),
    ('a/b', 'talker', '/robot/arm', '/robot/arm/a/b'),
    ('/chatter', 'talker', '/robot', '/chatter'),
    ('/a/b/c', 'n', '/x', '/a/b/c'),
    ('~', 'talker', '/', '/talker'),
    ('~', 'talker', '/robot', '/robot/talker'),
    ('~/status', 'talker', '/', '/talker/status'),
    ('~/status', 'talker', '/robot', '/robot/talker/status'),
    ('~/a/b', 'n', '/x/y', '/x/y/n/a/b'),
    ('{node}/out', 'talker', '/robot', '/robot/talker/out'),
    ('{ns}/out', 'talker', '/robot', '/robot/out'),
    ('/{node}', 'talker', '/', '/talker'),
    ('_hidden', 'n', '/', '/_hidden'),
    ('a1/_b2', 'n', '/', '/a1/_b2'),
])
def test_expand_topic_name(name, node, ns, expected):
    assert expand_topic_name(name, node, ns) == expected


@pytest.mark.parametrize('name, fragment', [
    ('chat*ter', "'*'"),
    ('*', "'*'"),
    ('/a/**', "'*'"),
    ('a$b', "'$'"),
    ('$*', "'$'"),
    ('a#b', "'#'"),
    ('a?b', "'?'"),
    ('a//b', "'//'"),
    ('/a/', 'empty token'),
    ('1abc', 'digit'),
    ('a/2b', 'digit'),
    ('a b', "' '"),
    ('a-b', "'-'"),
    ('a.b', "'.'"),
    ('ä', "'ä'"),
    ('~x', "'~' must be followed by '/'"),
    ('{nope}', 'substitution'),
    ('a}', 'substitution'),
    ('a{', 'substitution'),
    ('a~b', "'~'"),
    ('a/~/b', "'~'"),
    ('', 'non-empty'),
    ('/', "'/'"),
])
def test_expand_rejects_bad_names(name, fragment):
    with pytest.raises(InvalidNameError) as info:
        expand_topic_name(name, 'node', '/')
    assert fragment in str(info.value)
    assert '\n' not in str(info.value)
    assert isinstance(info.value, ValueError) and isinstance(info.value, ZrosError)


def test_expansion_error_mentions_original_name():
    with pytest.raises(InvalidNameError, match=r"expanded from '~/a\*'"):
        expand_topic_name('~/a*', 'n', '/')


def test_no_name_can_produce_a_zenoh_wildcard():
    for text in ('*', '**', '$*', 'a/*/b', 'a/**', 'x$*y', '~/*', '{node}*'):
        with pytest.raises(InvalidNameError):
            expand_topic_name(text, 'n', '/')


def test_non_string_name():
    with pytest.raises(TypeError):     # as rclpy (its C binding refuses it)
        expand_topic_name(None, 'n', '/')
    with pytest.raises(InvalidNameError):
        validate_full_name(5)


# -- node names and namespaces ------------------------------------------------------------
@pytest.mark.parametrize('name', ['talker', '_hidden', 'a1', 'A_b_C', 'x'])
def test_valid_node_names(name):
    assert validate_node_name(name) == name


@pytest.mark.parametrize('name, fragment', [
    ('', 'non-empty'), ('1talker', 'start with a letter'), ('a/b', "'a/b'"), ('a*', "'*'"),
    ('a$', "'$'"), ('a#', "'#'"), ('a?', "'?'"), ('tal ker', "' '"), ('~', "'~'"), ('a-b', "'-'"),
])
def test_invalid_node_names(name, fragment):
    with pytest.raises(InvalidNameError) as info:
        validate_node_name(name)
    assert fragment in str(info.value)


@pytest.mark.parametrize('given, expected', [
    (None, '/'), ('', '/'), ('/', '/'), ('robot', '/robot'), ('/robot', '/robot'), ('/robot/', '/robot'),
    ('a/b', '/a/b'), ('/a/b/', '/a/b'),
])
def test_normalize_namespace(given, expected):
    assert normalize_namespace(given) == expected


@pytest.mark.parametrize('bad', ['/a//b', '/1a', '/a*', 'relative', '/a$', '/a~b', '/{ns}'])
def test_invalid_namespaces(bad):
    with pytest.raises(InvalidNameError):
        if bad == 'relative':
            validate_namespace(bad)
        else:
            normalize_namespace(bad)


def test_fully_qualified_node_name():
    assert fully_qualified_node_name('/', 'talker') == '/talker'
    assert fully_qualified_node_name('/robot', 'talker') == '/robot/talker'


# -- remapping -------------------------------------------------------------------------------
def _remaps(*rules: str) -> Remappings:
    remaps = Remappings()
    for rule in rules:
        remaps.add(rule)
    return remaps


def test_simple_remap():
    remaps = _remaps('chatter:=news')
    assert remaps.apply('/chatter', 'talker', '/') == '/news'
    assert remaps.apply('/other', 'talker', '/') == '/other'


def test_remap_expands_both_sides_in_the_node_namespace():
    remaps = _remaps('chatter:=news')
    assert remaps.apply('/robot/chatter', 'talker', '/robot') == '/robot/news'
    # a relative rule does not touch the same name under another namespace
    assert remaps.apply('/chatter', 'talker', '/robot') == '/chatter'
    assert _remaps('/chatter:=/a/b').apply('/chatter', 'talker', '/robot') == '/a/b'
    assert _remaps('~/out:=/x').apply('/robot/talker/out', 'talker', '/robot') == '/x'
    assert _remaps('chatter:=~/mine').apply('/chatter', 'talker', '/') == '/talker/mine'


def test_first_matching_rule_wins():
    remaps = _remaps('chatter:=first', 'chatter:=second')
    assert remaps.apply('/chatter', 'talker', '/') == '/first'


def test_node_specific_rules():
    remaps = _remaps('talker:chatter:=x', 'listener:chatter:=y')
    assert remaps.apply('/chatter', 'talker', '/') == '/x'
    assert remaps.apply('/chatter', 'listener', '/') == '/y'
    assert remaps.apply('/chatter', 'other', '/') == '/chatter'
    # the rule names the node's original name, also after __node renamed it
    assert remaps.apply('/chatter', 'renamed', '/', original_node_name='talker') == '/x'


def test_node_name_and_namespace_overrides():
    remaps = _remaps('__node:=x', '__ns:=/robot')
    assert remaps.node_overrides('talker') == ('x', '/robot')
    assert _remaps('__name:=y').node_overrides('talker') == ('y', None)
    assert _remaps('__ns:=robot').node_overrides('talker') == (None, '/robot')
    specific = _remaps('talker:__node:=t2', 'talker:__ns:=/ns')
    assert specific.node_overrides('talker') == ('t2', '/ns')
    assert specific.node_overrides('listener') == (None, None)
    # __node/__ns are not topic rules
    assert specific.apply('/__node', 'talker', '/') == '/__node'


@pytest.mark.parametrize('rule, fragment', [
    ('chatter', "expected 'from:=to'"),
    (':=x', 'empty side'),
    ('chatter:=', 'empty side'),
    ('__node:=1x', '1x'),
    ('__node:=a/b', 'a/b'),
    ('__ns:=/a//b', '/a//b'),
])
def test_bad_remapping_rules(rule, fragment):
    with pytest.raises(InvalidNameError) as info:
        Remappings().add(rule)
    assert fragment in str(info.value)


def test_bad_rule_target_is_rejected_when_applied():
    remaps = _remaps('chatter:=bad*name')
    with pytest.raises(InvalidNameError, match="'\\*'"):
        remaps.apply('/chatter', 'talker', '/')


# -- --ros-args ----------------------------------------------------------------------------------
def test_parse_ros_args():
    args = parse_ros_args(['prog', 'user_arg', '--ros-args', '-r', 'a:=b', '--remap', '__node:=n',
                           '-p', 'rate:=2.5', '--params-file', 'p.yaml', '--log-level', 'debug',
                           '--log-level', 'talker:=warn', '--disable-rosout-logs', '--', 'tail'])
    assert args.remaps == ['a:=b', '__node:=n']
    assert args.params == [('rate', '2.5')]
    assert args.params_files == ['p.yaml']
    assert args.log_levels == [('', 'debug'), ('talker', 'warn')]
    assert args.disable_rosout
    assert remove_ros_args(['prog', 'user_arg', '--ros-args', '-r', 'a:=b', '--', 'tail']) == \
        ['prog', 'user_arg', 'tail']


@pytest.mark.parametrize('argv, fragment', [
    (['--ros-args', '--bogus'], "'--bogus'"),
    (['--ros-args', '-r'], "'-r' needs a value"),
    (['--ros-args', '-r', 'nope'], "'nope'"),
    (['--ros-args', '-p', 'nope'], "'nope'"),
    (['--ros-args', '-p', ':=1'], 'no name'),
])
def test_bad_ros_args(argv, fragment):
    with pytest.raises(RosArgsError) as info:
        parse_ros_args(argv)
    assert fragment in str(info.value)


# -- names through a node ------------------------------------------------------------------------
