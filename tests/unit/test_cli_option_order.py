"""Options before or among the positionals, as ros2cli accepts them and the courses print them
(`ros2 action send_goal /navigate_to_pose nav2_msgs/NavigateToPose --feedback "{pose: ...}"`):
every verb's parser. The course's send_goal against a real action server:
tests/integration/test_cli_option_order_live.py (more real commands with options first:
tests/integration/test_cli_formats.py)."""
from __future__ import annotations

import argparse

import pytest

from zros.cli.main import VERBS, build_parser


def _leaf_parsers(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(words, parser) for every command that reads options and positionals itself."""
    subparsers = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subparsers:
        yield path, parser
    for action in subparsers:
        for name, child in action.choices.items():
            yield from _leaf_parsers(child, path + (name,))


def _placeable_options(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    return [a for a in parser._actions if a.option_strings and a.nargs in (0, None) and a.dest != 'help']


def _every_verb():
    """Every command with a positional and an option to place before it. `zros run`, `python`
    and `launch` are left out: what follows their positionals goes to the program or the
    launch file (launch reads its own options after the file; tests/integration/test_launch_run.py)."""
    for verb in VERBS:
        for words, parser in _leaf_parsers(build_parser(verb)):
            positionals = [a for a in parser._actions if not a.option_strings]
            if (words[0] == verb   # the other verbs' parsers are empty in build_parser(verb)
                    and positionals and _placeable_options(parser)
                    and all(a.nargs != argparse.REMAINDER for a in positionals)):
                yield pytest.param(words, parser, id=' '.join(words))


def test_the_courses_commands_are_among_those_checked():
    checked = {' '.join(words) for words, _ in (p.values for p in _every_verb())}
    assert {'action send_goal', 'topic echo', 'topic pub', 'service call', 'param set'} <= checked


@pytest.mark.parametrize('words, parser', list(_every_verb()))
def test_every_verb_reads_an_option_before_its_positionals(words, parser):
    """The same namespace whether an option comes first, among or after the positionals."""
    positionals = [a for a in parser._actions if not a.option_strings]
    option = _placeable_options(parser)[0]
    value = [] if option.nargs == 0 else [str(option.choices[0]) if option.choices else '7']
    placed = [option.option_strings[-1], *value]
    values = [f'value{i}' for i, _ in enumerate(positionals)]   # one word each, '?', '*' and '+' alike
    top = build_parser(words[0])
    after = vars(top.parse_args([*words, *values, *placed]))
    assert vars(top.parse_args([*words, *placed, *values])) == after
    assert vars(top.parse_args([*words, values[0], *placed, *values[1:]])) == after
    assert after[option.dest] != option.default


def test_option_values_before_positionals_and_negative_values():
    parser = build_parser('topic')
    pub = parser.parse_args(['topic', 'pub', '-r', '2', '-t', '3', '/x', 'std_msgs/msg/String', '{data: hi}'])
    assert (pub.rate, pub.times, pub.topic_name, pub.values) == (2.0, 3, '/x', '{data: hi}')
    negative = parser.parse_args(['topic', 'pub', '--rate', '-1', '/x', 'std_msgs/msg/String', '{data: hi}'])
    assert (negative.rate, negative.values) == (-1.0, '{data: hi}')
    once = parser.parse_args(['topic', 'pub', '/x', '-1', 'std_msgs/msg/String', '{data: hi}'])
    assert once.once and once.values == '{data: hi}'
    param = build_parser('param').parse_args(['param', 'set', '--timeout', '2', '/n', 'p', '-5'])
    assert (param.timeout, param.node_name, param.parameter_name, param.value) == (2.0, '/n', 'p', '-5')


def test_python_takes_a_file_or_a_module_with_their_arguments():
    parser = build_parser()
    as_module = parser.parse_args(['python', '-m', 'pytest', '-q', 'test/'])
    assert as_module.module == ['pytest', '-q', 'test/'] and as_module.file is None
    as_file = parser.parse_args(['python', 'node.py', '-m', 'x', '--ros-args', '-r', 'a:=b'])
    assert as_file.module is None and as_file.file == 'node.py'
    assert as_file.argv == ['-m', 'x', '--ros-args', '-r', 'a:=b']   # the program's own -m
