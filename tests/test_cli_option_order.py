"""Options before or among the positionals, as ros2cli accepts them and the courses print them
(`ros2 action send_goal /navigate_to_pose nav2_msgs/NavigateToPose --feedback "{pose: ...}"`):
every verb's parser, then the course's send_goal against a real action server (more real
commands with options first: tests/test_cli_formats.py)."""
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
    launch file (launch reads its own options after the file; tests/test_launch_run.py)."""
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


@pytest.fixture(autouse=True)
def _isolated(module_domain):
    """Every CLI call of this module runs in the module's test domain."""


def test_action_send_goal_with_feedback_before_the_goal(module_spawn, zros_cli):
    """The course's order: `send_goal NAME TYPE --feedback GOAL`."""
    module_spawn.node('demo_nodes', 'fibonacci_action_server', '--ros-args', '-p', 'step_period:=0.02')
    sent = zros_cli('action', 'send_goal', '/fibonacci', 'action_tutorials_interfaces/action/Fibonacci',
                    '--feedback', '{order: 3}', timeout=30)
    assert sent.returncode == 0, sent
    assert '     order: 3' in sent.stdout.splitlines(), sent
    assert 'Feedback:' in sent.stdout and sent.stdout.rstrip().endswith('Goal finished with status: SUCCEEDED'), sent
    first = zros_cli('action', 'send_goal', '-f', '--timeout', '20', '/fibonacci',
                     'action_tutorials_interfaces/action/Fibonacci', '{order: 2}', timeout=30)
    assert first.returncode == 0 and 'Feedback:' in first.stdout, first
    assert '- 0\n- 1\n- 1\n' in first.stdout, first
