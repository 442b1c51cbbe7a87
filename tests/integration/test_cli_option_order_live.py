"""The course's `action send_goal` with its options first, against a real action server (every
verb's parser: tests/unit/test_cli_option_order.py)."""
from __future__ import annotations

import pytest


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
