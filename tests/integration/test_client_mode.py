"""Client mode without its router: a node waits and retries instead of exiting, and joins as
soon as the router is up; a command gives up after a bounded wait (issue 20, item 5)."""
from __future__ import annotations

import json
import socket
import sys
import time

import pytest


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


@pytest.fixture
def client_config(domain, tmp_path, monkeypatch):
    """A ZROS_CONFIG in client mode, dialling a router port where nothing listens yet."""
    port = _free_port()
    path = tmp_path / 'client.json5'
    path.write_text(json.dumps({'mode': 'client', 'connect': {'endpoints': [f'tcp/127.0.0.1:{port}']}}))
    monkeypatch.setenv('ZROS_CONFIG', str(path))
    return port


def test_a_client_node_waits_for_its_router_and_then_joins(client_config, spawn, zros_cli, monkeypatch):
    talker = spawn.node('demo_nodes', 'talker')
    talker.wait_for_output('cannot reach tcp/127.0.0.1', timeout=15)
    time.sleep(1.0)
    assert talker.popen.poll() is None, talker.output()        # still trying, not exited
    assert talker.output().count('cannot reach') == 1          # one line, not one per attempt
    monkeypatch.delenv('ZROS_CONFIG')
    spawn(sys.executable, '-m', 'zros', 'router', '--listen', f'tcp/127.0.0.1:{client_config}', name='router')
    talker.wait_for_output('Publishing:', timeout=20)
    monkeypatch.setenv('ZROS_CONNECT', f'tcp/127.0.0.1:{client_config}')
    echo = zros_cli('topic', 'echo', '--once', '--timeout', '15', '/chatter', 'std_msgs/msg/String', timeout=30)
    assert echo.returncode == 0 and 'Hello World' in echo.stdout, echo


def test_a_client_command_without_its_router_fails_within_seconds(client_config, zros_cli):
    started = time.monotonic()
    result = zros_cli('node', 'list', timeout=20)
    assert time.monotonic() - started < 10
    assert result.returncode == 1, result
    assert 'cannot reach tcp/127.0.0.1' in result.stderr and 'cannot open the Zenoh session' in result.stderr
    assert 'Traceback' not in result.stderr


def test_a_client_node_waiting_for_its_router_stops_on_signals(client_config, spawn):
    """No context exists yet for a signal to shut down: the wait itself ends."""
    import signal
    waiting = {signum: spawn.node('demo_nodes', 'talker')
               for signum in (signal.SIGINT, signal.SIGTERM)}
    for signum, child in waiting.items():
        child.wait_for_output('cannot reach tcp/127.0.0.1', timeout=15)
        child.signal(signum)
    for signum, child in waiting.items():
        child.wait(5)
        assert 'Traceback' not in child.output(), child.output()
    assert 'stopped by a signal while waiting for the router' in waiting[signal.SIGTERM].output()
