"""The programs in examples/ run as examples/README.md says, as plain `python examples/X.py`:
the talker/listener pair talks, the service pair answers, bad input is one line, and every
example imports and explains its command line."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

EXAMPLES = REPO / 'examples'
PROGRAMS = sorted(path.name for path in EXAMPLES.glob('*.py') if path.name != 'common.py')   # common: their shared CLI


def example(name: str) -> tuple[str, str]:
    """The argv head that runs examples/`name` as a user does: `python examples/name`."""
    return sys.executable, str(EXAMPLES / name)


def test_every_example_is_listed_in_the_readme():
    readme = (EXAMPLES / 'README.md').read_text(encoding='utf-8')
    assert len(PROGRAMS) >= 8
    assert [name for name in PROGRAMS if f'({name})' not in readme] == []


@pytest.mark.parametrize('name', PROGRAMS)
def test_each_example_imports_and_explains_its_command_line(name):
    result = subprocess.run([*example(name), '--help'], capture_output=True, text=True, timeout=60, cwd=REPO)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f'usage: {Path(name).stem} ')


def test_the_talker_and_the_listener_talk(spawn):
    listener = spawn.command(*example('listener.py'), '--count', '3', name='listener')
    talker = spawn.command(*example('talker.py'), '--period', '0.2', name='talker')
    assert listener.wait(timeout=60) == 0, listener.output()
    assert listener.output().count('I heard: [Hello World: ') == 3
    assert "Publishing: 'Hello World: 1'" in talker.output()
    assert talker.stop() == 0, talker.output()   # Ctrl-C ends it cleanly


def test_the_service_client_gets_the_servers_sum(spawn):
    server = spawn.command(*example('add_two_ints_server.py'), name='server')
    client = spawn.command(*example('add_two_ints_client.py'), '3', '4', name='client')
    assert client.wait(timeout=60) == 0, client.output() + server.output()
    assert 'Result of add_two_ints: for 3 + 4 = 7' in client.output()
    assert 'Incoming request: a: 3 b: 4' in server.wait_for_output('Incoming request', timeout=10)
    assert server.stop() == 0, server.output()


def test_a_client_without_a_server_says_so_in_one_line(domain):
    result = subprocess.run([*example('add_two_ints_client.py'), '1', '2', '--timeout', '1'],
                            capture_output=True, text=True, timeout=60, cwd=REPO)
    assert result.returncode == 1
    assert result.stderr.strip() == "add_two_ints_client: service 'add_two_ints' not available after 1 s"


def test_the_parameters_example_takes_ros_args_and_refuses_a_bad_period(domain):
    result = subprocess.run([*example('parameters.py'), '--once', '--ros-args', '-p', 'greeting:=Hi'],
                            capture_output=True, text=True, timeout=60, cwd=REPO)
    assert result.returncode == 0, result.stderr
    assert '[parameters_example]: greeting: Hi' in result.stderr
    assert "successful=False, reason='period must be greater than 0'" in result.stderr
