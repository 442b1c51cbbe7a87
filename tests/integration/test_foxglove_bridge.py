"""`zros run foxglove_bridge foxglove_bridge` seen by a client made only of Foxglove's npm packages
(tests/data/foxglove_client.js): it subscribes, decodes with the advertised schema, publishes,
calls services, and the bridge survives malformed frames.

The npm packages are installed once into ~/.cache/zros-test-npm; without node/npm, or when
the install fails (no registry), the tests skip and say why.
"""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any, Callable

import pytest

from conftest import REPO, wait_until

NPM_PACKAGES = ('@foxglove/ws-protocol', '@foxglove/rosmsg', '@foxglove/rosmsg2-serialization', 'ws')
NPM_CACHE = Path.home() / '.cache' / 'zros-test-npm'
CLIENT = REPO / 'tests' / 'data' / 'foxglove_client.js'
TB3_MAP = REPO / 'nodes' / 'turtlebot3_navigation2' / 'map' / 'map.yaml'


@pytest.fixture(scope='module')
def node_modules() -> Path:
    """The npm packages' folder, installed on first use."""
    node, npm = shutil.which('node'), shutil.which('npm')
    if not node or not npm:
        pytest.skip('node and npm are needed for the Foxglove client')
    modules = NPM_CACHE / 'node_modules'
    if not all((modules / name / 'package.json').exists() for name in NPM_PACKAGES):
        NPM_CACHE.mkdir(parents=True, exist_ok=True)
        if not (NPM_CACHE / 'package.json').exists():
            (NPM_CACHE / 'package.json').write_text('{"name": "zros-test-npm", "private": true}\n')
        try:
            done = subprocess.run([npm, 'install', '--no-audit', '--no-fund', *NPM_PACKAGES], cwd=NPM_CACHE,
                                  capture_output=True, text=True, timeout=300)
        except subprocess.TimeoutExpired:
            pytest.skip('npm install of the Foxglove client packages took over 300 s')
        if done.returncode != 0:
            pytest.skip(f'npm install of the Foxglove client packages failed: {done.stderr.strip()[-300:]}')
    return modules


def start_bridge(spawn: Any, *params: str) -> tuple[Any, str]:
    """The bridge on a free loopback port; returns (process, ws:// URL)."""
    args = ['-p', 'address:=127.0.0.1', '-p', 'port:=0']
    for param in params:
        args += ['-p', param]
    bridge = spawn.node('foxglove_bridge', 'foxglove_bridge', '--ros-args', *args)
    line = bridge.wait_for_output('listening on ws://', timeout=30)
    port = re.search(r'listening on ws://[\d.]+:(\d+)', bridge.output() + line).group(1)
    return bridge, f'ws://127.0.0.1:{port}'


@pytest.fixture
def run_client(node_modules: Path) -> Callable[..., tuple[int, list[dict]]]:
    """`run_client(plan)` runs the Foxglove client to its end: (exit code, its JSON events)."""
    def run(plan: dict, timeout_s: float = 30.0) -> tuple[int, list[dict]]:
        plan = {'timeoutMs': int(timeout_s * 1000), **plan}
        done = subprocess.run(['node', str(CLIENT), json.dumps(plan)], capture_output=True, text=True,
                              timeout=timeout_s + 15, env={'NODE_PATH': str(node_modules), 'PATH': '/usr/bin:/bin'})
        events = [json.loads(line) for line in done.stdout.splitlines() if line.startswith('{')]
        return done.returncode, events + [{'event': 'stderr', 'text': done.stderr}]
    return run


def messages(events: list[dict], topic: str) -> list[dict]:
    return [e for e in events if e['event'] == 'message' and e['topic'] == topic]


def test_chatter_is_decoded_with_the_advertised_ros2msg_schema(spawn, run_client):
    talker = spawn.node('demo_nodes', 'talker')
    bridge, url = start_bridge(spawn)
    code, events = run_client({'url': url, 'subscribe': ['/chatter'], 'count': 3})
    assert code == 0, (events, bridge.output(), talker.output())
    got = messages(events, '/chatter')
    assert [(e['schemaName'], e['encoding']) for e in got] == [('std_msgs/msg/String', 'cdr')] * 3
    assert all(re.fullmatch(r'Hello World: \d+', e['message']['data']) for e in got), got


def test_malformed_frames_get_an_error_and_the_bridge_keeps_serving(spawn, run_client):
    spawn.node('demo_nodes', 'talker')
    bridge, url = start_bridge(spawn)
    code, events = run_client({'url': url, 'subscribe': ['/chatter'], 'count': 1, 'malformed': True})
    assert code == 0, (events, bridge.output())
    statuses = [e['text'] for e in events if e['event'] == 'status']
    assert any('key must be a string' in s for s in statuses), statuses     # not JSON
    assert any('noSuchOp' in s for s in statuses), statuses                 # unknown op
    assert any('binary opcode' in s for s in statuses), statuses            # unknown binary frame
    # ... and a second client, after the first one's garbage, is served as usual.
    code, events = run_client({'url': url, 'subscribe': ['/chatter'], 'count': 1})
    assert code == 0 and messages(events, '/chatter'), (events, bridge.output())
    assert 'Traceback' not in bridge.output()


def test_a_client_calls_a_zros_service_with_cdr(spawn, run_client):
    spawn.node('demo_nodes', 'add_two_ints_server')
    bridge, url = start_bridge(spawn)
    code, events = run_client({'url': url, 'call': {'service': '/add_two_ints', 'request': {'a': 2, 'b': 40}}})
    assert code == 0, (events, bridge.output())
    assert [e['message'] for e in events if e['event'] == 'response'] == [{'sum': 42}]


def test_a_client_channel_publishes_into_zros(spawn, run_client, probe):
    from interfaces.std_msgs.msg import String
    got: list = []
    probe.create_subscription(String, '/from_foxglove', got.append, 10)
    bridge, url = start_bridge(spawn)
    plan = {'url': url, 'timeoutMs': 4000,
            'publish': {'topic': '/from_foxglove', 'schemaName': 'std_msgs/String', 'schema': 'string data',
                        'message': {'data': 'hello from foxglove'}, 'times': 30}}
    run_client(plan, timeout_s=4)   # publishes for 3 s, then times out by design
    wait_until(lambda: got, 10, message=lambda: f'nothing on /from_foxglove\n{bridge.output()}')
    assert got[0].data == 'hello from foxglove'


def test_scan_map_and_tf_of_the_turtlebot3_world_are_decoded(spawn, run_client, monkeypatch):
    monkeypatch.setenv('TURTLEBOT3_MODEL', 'burger')
    world = spawn(sys.executable, '-m', 'zros', 'launch', 'turtlebot3_gazebo', 'turtlebot3_world.launch.py',
                  name='world')
    spawn.node('nav2_map_server', 'map_server', '--ros-args', '-p', f'yaml_filename:={TB3_MAP}',
               '-p', 'autostart:=true')
    bridge, url = start_bridge(spawn)
    code, events = run_client({'url': url, 'subscribe': ['/scan', '/map', '/tf'], 'count': 1}, timeout_s=60)
    assert code == 0, '\n'.join(map(str, events)) + bridge.output() + world.output()
    scan, = messages(events, '/scan')
    assert scan['schemaName'] == 'sensor_msgs/msg/LaserScan'
    assert scan['message']['header']['frame_id'] == 'base_scan' and scan['message']['ranges']['length'] == 360
    grid, = messages(events, '/map')
    assert grid['schemaName'] == 'nav_msgs/msg/OccupancyGrid' and grid['message']['header']['frame_id'] == 'map'
    info = grid['message']['info']
    assert grid['message']['data']['length'] == info['width'] * info['height'] > 0
    assert info['resolution'] == pytest.approx(0.05)
    tf, = messages(events, '/tf')
    assert tf['schemaName'] == 'tf2_msgs/msg/TFMessage'
    assert {t['header']['frame_id'] for t in tf['message']['transforms']} <= {'odom', 'base_footprint', 'base_link'}
    assert tf['message']['transforms'], tf


def test_parameters_are_read_and_set_as_node_dot_name(spawn, run_client, zros_cli):
    spawn.node('demo_nodes', 'talker')
    bridge, url = start_bridge(spawn)
    plan = {'url': url, 'getParameters': ['/talker.use_sim_time'], 'until': ['parameters']}
    code, events = run_client(plan)
    assert code == 0, (events, bridge.output())
    got = next(e for e in events if e['event'] == 'parameters')
    assert got['parameters'] == [{'name': '/talker.use_sim_time', 'value': False}]
    plan = {'url': url, 'setParameters': [{'name': '/talker.use_sim_time', 'value': True}], 'until': ['parameters']}
    code, events = run_client(plan)
    assert code == 0, (events, bridge.output())
    result = zros_cli('param', 'get', '/talker', 'use_sim_time')
    assert result.returncode == 0 and 'True' in result.stdout, result
    # A value of the wrong type is refused with the node's reason, and the value stays.
    plan = {'url': url, 'setParameters': [{'name': '/talker.use_sim_time', 'value': 'yes'}],
            'until': ['statusMatch'], 'untilStatus': 'not set'}
    code, events = run_client(plan)
    assert code == 0, (events, bridge.output())
    status = next(e['text'] for e in events if e['event'] == 'status' and 'not set' in e['text'])
    assert status.startswith("parameter '/talker.use_sim_time' not set:"), status


def test_a_parameter_change_is_pushed_to_subscribed_clients(spawn, run_client, zros_cli):
    import threading
    spawn.node('demo_nodes', 'parameter_blackboard')
    bridge, url = start_bridge(spawn)
    outcome: list = []
    client = threading.Thread(target=lambda: outcome.append(run_client(
        {'url': url, 'subscribeParameters': ['/parameter_blackboard.colour'], 'until': ['parameters']})))
    client.start()

    def set_and_see_the_push() -> bool:
        # When the client's subscription reaches the server is not visible from here: set the
        # value again until the client has had its push (and ended).
        assert zros_cli('param', 'set', '/parameter_blackboard', 'colour', 'green').returncode == 0
        client.join(timeout=1)
        return not client.is_alive()
    wait_until(set_and_see_the_push, 30, message=bridge.output)
    code, events = outcome[0]
    assert code == 0, (events, bridge.output())
    pushed = [p for e in events if e['event'] == 'parameters' for p in e['parameters']]
    assert {'name': '/parameter_blackboard.colour', 'value': 'green'} in pushed, events


def test_channels_and_the_connection_graph_follow_the_zros_graph(spawn, run_client, probe):
    import threading
    talker = spawn.node('demo_nodes', 'talker')
    bridge, url = start_bridge(spawn)
    plan = {'url': url, 'subscribe': ['/chatter'], 'graph': True, 'until': ['graph'], 'count': 1}
    code, events = run_client(plan)
    assert code == 0, (events, bridge.output())
    published = {t['name']: t['publisherIds'] for e in events if e['event'] == 'graph'
                 for t in e['update']['publishedTopics']}
    assert '/talker' in published.get('/chatter', []), published
    # The client has gone: its subscription's zros subscription goes with it.
    wait_until(lambda: probe.count_subscribers('/chatter') == 0, 15, message='the bridge to unsubscribe /chatter')
    # A client listens to /chatter; when the talker goes, the client is told the channel is gone.
    outcome: list = []
    client = threading.Thread(target=lambda: outcome.append(run_client(
        {'url': url, 'subscribe': ['/chatter'], 'count': 0, 'until': ['unadvertise']})))
    client.start()
    wait_until(lambda: probe.count_subscribers('/chatter') >= 1, 15, message='the bridge subscribing /chatter')
    talker.kill()
    client.join(timeout=60)
    code, events = outcome[0]
    assert code == 0, '\n'.join(map(str, events)) + bridge.output()
    advertised = {c['id']: c['topic'] for e in events if e['event'] == 'advertise' for c in e['channels']}
    removed = [advertised.get(i) for e in events if e['event'] == 'unadvertise' for i in e['channelIds']]
    assert '/chatter' in removed, events


CLOCK = '''
import time, zros
from zros.node import Node
from interfaces.rosgraph_msgs.msg import Clock
with zros.init():
    node = Node('clock_source')
    pub = node.create_publisher(Clock, '/clock', 10)
    for i in range(10_000):
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = 42, i
        pub.publish(msg)
        time.sleep(0.05)
'''


def test_with_use_sim_time_clock_is_the_server_time(spawn, run_client):
    spawn.script(CLOCK, name='clock')
    bridge, url = start_bridge(spawn, 'use_sim_time:=true')
    code, events = run_client({'url': url, 'until': ['time']})
    assert code == 0, (events, bridge.output())
    stamp = int(next(e for e in events if e['event'] == 'time')['timestamp'])
    assert 42_000_000_000 <= stamp < 42_000_010_000, stamp


def test_a_message_over_send_buffer_limit_is_counted_and_reported_and_others_flow(spawn, run_client):
    spawn.node('demo_nodes', 'talker')
    spawn(sys.executable, '-m', 'zros', 'topic', 'pub', '-r', '5', '/big', 'std_msgs/msg/String',
          "{data: '" + 'x' * 5000 + "'}", name='big')
    bridge, url = start_bridge(spawn, 'send_buffer_limit:=1000')
    code, events = run_client({'url': url, 'subscribe': ['/big', '/chatter'], 'count': 0, 'until': ['statusMatch'],
                               'untilStatus': "'/big'"})
    assert code == 0, (events, bridge.output())
    status = next(e['text'] for e in events if e['event'] == 'status' and "'/big'" in e['text'])
    assert "'/big': 1 message(s) not sent, larger than send_buffer_limit (1000 bytes" in status, status
    code, events = run_client({'url': url, 'subscribe': ['/chatter'], 'count': 1})
    assert code == 0 and messages(events, '/chatter'), (events, bridge.output())
