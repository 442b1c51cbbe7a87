"""rosbridge_server through its launch file (the WebSocket server and rosapi), spoken to by a
plain WebSocket client: the protocol's ops against real demo nodes, CBOR frames, a web client
serving a zros service, rosapi's graph and parameter services, and bad input answered with a
status error to that client while the bridge goes on serving the others."""
from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from typing import Any

import pytest

from conftest import REPO, assert_clean_failure, run_cli, wait_until

PORT_LINE = re.compile(r'Rosbridge WebSocket server started on port (\d+)')
MAX_MESSAGE_SIZE = 200_000
SEND_BUFFER_LIMIT = 1_000_000


@pytest.fixture(autouse=True)
def _isolated(module_domain: int) -> None:
    """Every CLI call of this module runs in the module's domain."""


@pytest.fixture(scope='module')
def bridge(module_spawn: Any) -> tuple[str, Any]:
    """`zros launch rosbridge_server rosbridge_websocket_launch.xml` on a free port, with the demo
    talker and add_two_ints_server beside it."""
    talker = module_spawn.node('demo_nodes_py', 'talker')
    module_spawn.node('demo_nodes_py', 'add_two_ints_server')
    launch = module_spawn.command(sys.executable, '-m', 'zros', 'launch', 'rosbridge_server', 'rosbridge_websocket_launch.xml',
                                  'port:=0', 'address:=127.0.0.1', f'max_message_size:={MAX_MESSAGE_SIZE}',
                                  f'send_buffer_limit:={SEND_BUFFER_LIMIT}', name='rosbridge')
    output = launch.wait_for_output('Rosbridge WebSocket server started on port', timeout=30)
    talker.wait_for_output("Publishing: 'Hello World: 1'", timeout=15)
    url = f'ws://127.0.0.1:{PORT_LINE.search(output).group(1)}'
    probe = Client(url)
    try:   # rosapi, the launch file's other node, serves once its services answer
        wait_until(lambda: _answers(probe, '/rosapi/topics'), 30, message='/rosapi/topics through the bridge')
    finally:
        probe.close()
    return url, launch


@pytest.fixture(scope='module')
def bridge_url(bridge: tuple[str, Any]) -> str:
    return bridge[0]


def _answers(client: 'Client', service: str) -> bool:
    client.send(op='call_service', id='probe', service=service)
    reply = client.wait_for(lambda m: m.get('id') == 'probe')
    return reply['op'] == 'service_response' and reply['result']


class Client:
    """A synchronous WebSocket client that reads rosbridge frames until the one it waits for."""

    def __init__(self, url: str) -> None:
        from websockets.sync.client import connect
        self.ws = connect(url, open_timeout=10, max_size=None)

    def send(self, **op: Any) -> None:
        self.ws.send(json.dumps(op))

    def wait_for(self, predicate: Any, timeout: float = 15.0) -> dict:
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise AssertionError('no matching rosbridge frame within the timeout')
            try:
                frame = self.ws.recv(timeout=left)
            except TimeoutError:
                continue
            message = _decode(frame)
            if predicate(message):
                return message

    def close(self) -> None:
        self.ws.close()


class StalledClient:
    """A WebSocket client that subscribes and then never reads: a raw socket with a small
    receive buffer (websockets' own clients read ahead into their queues)."""

    def __init__(self, url: str, topic: str) -> None:
        import base64
        import os
        import socket
        self.sock = socket.socket()
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        self.sock.settimeout(10)
        self.sock.connect(('127.0.0.1', int(url.rsplit(':', 1)[1])))
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall(f'GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n'
                          f'Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n'.encode())
        reply = b''
        while b'\r\n\r\n' not in reply:
            reply += self.sock.recv(1)
        assert reply.startswith(b'HTTP/1.1 101'), reply
        payload = json.dumps({'op': 'subscribe', 'topic': topic, 'type': 'std_msgs/msg/String'}).encode()
        mask = os.urandom(4)
        assert len(payload) < 126
        self.sock.sendall(bytes([0x81, 0x80 | len(payload)]) + mask
                          + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def close(self) -> None:
        self.sock.close()


def _decode(frame: str | bytes) -> dict:
    if isinstance(frame, bytes):
        import cbor2
        return cbor2.loads(frame)
    return json.loads(frame)


@pytest.fixture
def client(bridge_url: str) -> Client:
    c = Client(bridge_url)
    yield c
    c.close()


def _cli(*args: str) -> subprocess.Popen:
    """`zros ARGS` running beside the test (run_cli waits; these must run while the test acts)."""
    return subprocess.Popen([sys.executable, '-m', 'zros.cli.main', *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True, cwd=REPO)


def _op(name: str, **fields: Any):
    return lambda m: m.get('op') == name and all(m.get(k) == v for k, v in fields.items())


def test_subscribe_chatter_then_unsubscribe(client: Client) -> None:
    client.send(op='subscribe', id='s1', topic='/chatter', type='std_msgs/msg/String')
    message = client.wait_for(_op('publish', topic='/chatter'))
    assert message['msg']['data'].startswith('Hello World: ')
    client.send(op='unsubscribe', id='s1', topic='/chatter')
    client.send(op='call_service', id='after', service='/rosapi/topics')   # a fence after the unsubscribe
    client.wait_for(_op('service_response', id='after'))
    with pytest.raises(AssertionError, match='no matching'):
        client.wait_for(_op('publish', topic='/chatter'), timeout=2.5)


def test_subscriptions_match_best_effort_and_latched_publishers(client: Client, module_spawn: Any) -> None:
    """A sensor's best-effort topic and a latched one (published once, before the client came)."""
    module_spawn.command(sys.executable, '-m', 'zros', 'topic', 'pub', '-r', '5', '--qos-reliability', 'best_effort',
                         '/be_words', 'std_msgs/msg/String', '{data: best effort}', name='best_effort')
    latched = module_spawn.command(sys.executable, '-m', 'zros', 'topic', 'pub', '-t', '1', '-w', '0', '--keep-alive', '60',
                                   '--qos-durability', 'transient_local', '/latched_words', 'std_msgs/msg/String',
                                   '{data: latched}', name='latched')
    wait_until(lambda: 'Publisher count: 1' in run_cli('topic', 'info', '/be_words').stdout, 15, message='/be_words')
    latched.wait_for_output('publishing #1', timeout=15)
    client.send(op='subscribe', topic='/be_words')
    client.send(op='subscribe', topic='/latched_words')
    seen: dict[str, dict] = {}

    def both(message: dict) -> bool:
        if message.get('op') == 'publish':
            seen[message['topic']] = message['msg']
        return len(seen) == 2
    client.wait_for(both)
    assert seen == {'/be_words': {'data': 'best effort'}, '/latched_words': {'data': 'latched'}}


def test_subscribe_with_cbor_gets_binary_frames(client: Client) -> None:
    client.send(op='subscribe', topic='/chatter', compression='cbor')   # type inferred from the graph
    frame = None
    deadline = time.monotonic() + 15
    while frame is None and time.monotonic() < deadline:
        raw = client.ws.recv(timeout=15)
        if isinstance(raw, bytes):
            frame = _decode(raw)
    assert frame is not None and frame['op'] == 'publish' and frame['msg']['data'].startswith('Hello World')


def test_call_service_and_rosapi(client: Client) -> None:
    client.send(op='call_service', id='c1', service='/add_two_ints', args={'a': 2, 'b': 40})
    response = client.wait_for(_op('service_response', id='c1'))
    assert response['result'] is True and response['values'] == {'sum': 42}
    client.send(op='call_service', id='c2', service='/add_two_ints', args=[5, 6])   # positional, as rosbridge allows
    assert client.wait_for(_op('service_response', id='c2'))['values'] == {'sum': 11}
    client.send(op='call_service', id='t', service='/rosapi/topics')
    topics = client.wait_for(_op('service_response', id='t'))['values']
    assert dict(zip(topics['topics'], topics['types']))['/chatter'] == 'std_msgs/msg/String'
    client.send(op='call_service', id='n', service='/rosapi/nodes')
    nodes = client.wait_for(_op('service_response', id='n'))['values']['nodes']
    assert {'/talker', '/add_two_ints_server', '/rosbridge_websocket', '/rosapi'} <= set(nodes)
    client.send(op='call_service', id='tt', service='/rosapi/topic_type', args={'topic': '/chatter'})
    assert client.wait_for(_op('service_response', id='tt'))['values'] == {'type': 'std_msgs/msg/String'}


def test_rosapi_parameters(client: Client) -> None:
    client.send(op='call_service', id='g', service='/rosapi/get_param',
                args={'name': '/talker:use_sim_time', 'default_value': ''})
    assert client.wait_for(_op('service_response', id='g'))['values'] == {'value': 'false'}
    for value in ('true', 'false'):   # and back, for the other tests
        client.send(op='call_service', id=value, service='/rosapi/set_param',
                    args={'name': '/add_two_ints_server:use_sim_time', 'value': value})
        client.wait_for(_op('service_response', id=value))
        result = run_cli('param', 'get', '/add_two_ints_server', 'use_sim_time')
        assert result.returncode == 0 and f'Boolean value is: {value.capitalize()}' in result.stdout, result
    client.send(op='call_service', id='m', service='/rosapi/get_param',
                args={'name': '/no_such_node:x', 'default_value': '"fallback"'})
    assert client.wait_for(_op('service_response', id='m'))['values'] == {'value': '"fallback"'}


def test_advertise_publish_reaches_zros(client: Client) -> None:
    client.send(op='advertise', topic='/web_words', type='std_msgs/String')
    echo = _cli('topic', 'echo', '/web_words', 'std_msgs/msg/String', '--once')
    try:
        deadline = time.monotonic() + 20
        while echo.poll() is None and time.monotonic() < deadline:
            client.send(op='publish', topic='/web_words', msg={'data': 'from the web'})
            time.sleep(0.2)
        out, err = echo.communicate(timeout=5)
    finally:
        echo.kill()
    assert echo.returncode == 0 and 'data: from the web' in out, (out, err)


def test_a_web_client_serves_a_zros_service(client: Client) -> None:
    client.send(op='advertise_service', service='/web_add', type='example_interfaces/srv/AddTwoInts')
    client.send(op='call_service', id='fence', service='/rosapi/services')
    client.wait_for(_op('service_response', id='fence'))
    cli = _cli('service', 'call', '/web_add', 'example_interfaces/srv/AddTwoInts', '{a: 20, b: 22}')
    try:
        request = client.wait_for(_op('call_service', service='/web_add'), timeout=20)
        assert request['args'] == {'a': 20, 'b': 22}
        client.send(op='service_response', id=request['id'], service='/web_add', values={'sum': 42}, result=True)
        out, err = cli.communicate(timeout=20)
    finally:
        cli.kill()
    assert cli.returncode == 0 and 'sum=42' in out, (out, err)


def test_malformed_json_gets_a_status_error_and_the_session_goes_on(client: Client) -> None:
    client.ws.send('{"op": "subscribe", "topic": ')
    status = client.wait_for(_op('status'))
    assert status['level'] == 'error' and 'not valid JSON' in status['msg']
    client.ws.send('[1, 2]')
    assert "'op'" in client.wait_for(_op('status'))['msg']
    client.send(op='call_service', id='ok', service='/add_two_ints', args={'a': 1, 'b': 1})
    assert client.wait_for(_op('service_response', id='ok'))['values'] == {'sum': 2}


def test_unknown_op_and_wrong_types_get_status_errors(client: Client) -> None:
    client.send(op='teleport', id='x1')
    status = client.wait_for(_op('status', id='x1'))
    assert status['level'] == 'error' and "unknown op 'teleport'" in status['msg']
    client.send(op='subscribe', id='x2', topic='/chatter', type='no_pkg/msg/Nothing')
    assert "unknown msg type 'no_pkg/msg/Nothing'" in client.wait_for(_op('status', id='x2'))['msg']
    client.send(op='advertise', id='x3', topic='/chatter', type='std_msgs/msg/Int32')
    assert 'already has type std_msgs/msg/String' in client.wait_for(_op('status', id='x3'))['msg']
    client.send(op='advertise', topic='/web_twist', type='geometry_msgs/msg/Twist')
    client.send(op='publish', id='x4', topic='/web_twist', msg={'linear': {'x': 'fast'}})
    assert "'linear.x'" in client.wait_for(_op('status', id='x4'))['msg']
    client.send(op='call_service', id='x5', service='/add_two_ints', args={'a': 'one'})
    assert "'a'" in client.wait_for(_op('status', id='x5'))['msg']
    client.send(op='call_service', id='x6', service='/nobody_serves_this')
    assert 'does not exist' in client.wait_for(_op('status', id='x6'))['msg']


def test_a_huge_message_is_refused_and_other_clients_keep_their_data(client: Client, bridge_url: str) -> None:
    other = Client(bridge_url)
    try:
        other.send(op='subscribe', topic='/chatter', type='std_msgs/msg/String')
        other.wait_for(_op('publish', topic='/chatter'))
        client.send(op='publish', id='big', topic='/web_big', type='std_msgs/msg/String',
                    msg={'data': 'x' * (MAX_MESSAGE_SIZE + 10)})
        assert 'larger than max_message_size' in client.wait_for(_op('status'))['msg']
        other.wait_for(_op('publish', topic='/chatter'))
        client.send(op='call_service', id='ok', service='/add_two_ints', args={'a': 3, 'b': 4})
        assert client.wait_for(_op('service_response', id='ok'))['values'] == {'sum': 7}
    finally:
        other.close()


def test_a_client_that_stops_reading_loses_its_oldest_frames_not_the_bridge(client: Client,
                                                                            bridge: tuple[str, Any]) -> None:
    url, launch = bridge
    stalled = StalledClient(url, '/web_flood')
    try:
        wait_until(lambda: 'Subscription count: 1' in run_cli('topic', 'info', '/web_flood').stdout, 15,
                   message="the stalled client's subscription")
        client.send(op='subscribe', topic='/web_flood', type='std_msgs/msg/String')
        client.send(op='advertise', topic='/web_flood', type='std_msgs/msg/String')
        flood = 'x' * 100_000
        for i in range(100):   # 10 MB for a client that reads none of it, ten times its send buffer
            client.send(op='publish', topic='/web_flood', msg={'data': f'{i:03d}{flood}'})
        last = client.wait_for(lambda m: m.get('op') == 'publish' and m['msg']['data'].startswith('099'), timeout=30)
        assert len(last['msg']['data']) == 100_003
        client.send(op='call_service', id='ok', service='/add_two_ints', args={'a': 5, 'b': 5})
        assert client.wait_for(_op('service_response', id='ok'))['values'] == {'sum': 10}
    finally:
        stalled.close()
    wait_until(lambda: re.search(r'client .*: \d+ frames were dropped \(send buffer full\)', launch.output()), 15,
               message='the count of dropped frames in the bridge log')


def test_port_in_use_is_a_one_line_error(bridge_url: str) -> None:
    port = bridge_url.rsplit(':', 1)[1]
    result = run_cli('run', 'rosbridge_server', 'rosbridge_websocket', '--ros-args', '-r', '__node:=second_bridge', '-p', f'port:={port}',
                     '-p', 'address:=127.0.0.1', timeout=30)
    assert_clean_failure(result, f'cannot listen on 127.0.0.1:{port}')


def test_a_port_out_of_range_is_a_one_line_error() -> None:
    result = run_cli('run', 'rosbridge_server', 'rosbridge_websocket', '--ros-args', '-r', '__node:=third_bridge',
                     '-p', 'port:=99999', timeout=30)
    assert_clean_failure(result, 'port 99999 is not a TCP port')
