"""Programs written for rclpy, the way ROS 2's examples and the course texts write them, ported
with `zros port` or run unmodified with `zros python` (the programs are in porting_programs/;
docs/porting.md reports the same check on the public examples and the course programs)."""
from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

import pytest

PROGRAMS = Path(__file__).parents[1] / 'porting_programs'


@pytest.fixture
def ported(tmp_path, zros_cli) -> Path:
    """A copy of the programs, ported for good by `zros port`."""
    target = tmp_path / 'ported'
    shutil.copytree(PROGRAMS, target)
    result = zros_cli('port', str(target))
    assert result.returncode == 0 and f'ported {len(list(PROGRAMS.glob("*.py")))} file(s)' in result.stderr, result
    code = ''.join(p.read_text() for p in target.glob('*.py'))
    assert 'import rclpy' not in code and 'from rclpy' not in code and 'from std_msgs' not in code
    return target


def _python(*argv: str) -> tuple[str, ...]:
    return (sys.executable, '-m', 'zros', 'python', *argv)


def test_an_asyncio_client_of_a_ported_action_server(ported, spawn):
    spawn(sys.executable, str(ported / 'fib_server.py'), name='fib_server')
    client = spawn(*_python(str(PROGRAMS / 'asyncio_client.py')), name='asyncio_client')
    output = client.wait_for_output('then: ', timeout=30)
    assert ("together: [array('i', [0, 1, 1, 2, 3]), array('i', [0, 1, 1, 2, 3, 5, 8])]" in output
            and "then: array('i', [0, 1, 1, 2])" in output), output
    assert client.wait(timeout=10) == 0


def test_parameters_through_the_blackboard_and_a_throttling_group(ported, spawn, tmp_path):
    spawn.node('demo_nodes_cpp', 'parameter_blackboard')
    params = tmp_path / 'params.yaml'
    params.write_text('/some_other_node:\n  ros__parameters:\n    wheels: 4\n    arm:\n      reach: 0.8\n')
    client = spawn(sys.executable, str(ported / 'blackboard_client.py'), str(params), name='blackboard_client')
    output = client.wait_for_output('blackboard: ', timeout=30)
    assert 'loaded wheels: True' in output and 'loaded arm.reach: True' in output, output
    assert "blackboard: {'speed': 0.5, 'wheels': 4, 'arm.reach': 0.8}" in output, output
    talker = spawn(*_python(str(PROGRAMS / 'throttled_talker.py')), name='throttled_talker')
    talker.wait_for_output('tick 4', timeout=20)   # three tokens, then one per refill (2 Hz)
    ticks = [int(n) for n in re.findall(r'tick (\d+)', talker.output())]
    assert ticks == list(range(1, len(ticks) + 1)) and len(ticks) < 10, talker.output()
