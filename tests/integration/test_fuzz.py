"""Malformed input from a raw Zenoh client, on every surface of a running node process: topics,
services, an action server and the parameter services. Each surface gets a few hundred
generated samples or requests that are invalid by construction; the node must drop or refuse
every one (counting each in `rejected`), print no traceback, stay alive and serve normally
afterwards. Bounded: a fixed seed, about 1500 messages, a few seconds."""
from __future__ import annotations

import json
import math
import os
import random
import struct
import time

import msgpack
import numpy as np
import pytest

from zros.node import Node

from interfaces.action_tutorials_interfaces.action import Fibonacci
from interfaces.example_interfaces.srv import AddTwoInts
from interfaces.rcl_interfaces.srv import GetParameters
from interfaces.sensor_msgs.msg import LaserScan
from interfaces.std_msgs.msg import String
from interfaces.std_srvs.srv import Trigger

TARGET = '''
import json, time
import zros
from zros.action import ActionServer
from zros.node import Node
from interfaces.action_tutorials_interfaces.action import Fibonacci
from interfaces.example_interfaces.srv import AddTwoInts
from interfaces.sensor_msgs.msg import LaserScan
from interfaces.std_msgs.msg import String
from interfaces.std_srvs.srv import Trigger


class Target(Node):
    """Callbacks that would fail on a malformed message (str methods, sums, int arithmetic)."""

    def __init__(self):
        super().__init__('fuzz_target')
        self.declare_parameter('speed', 1.5)
        self.subs = [self.create_subscription(String, '/fuzz/chatter', self.on_string, 1000),
                     self.create_subscription(LaserScan, '/fuzz/scan', self.on_scan, 1000)]
        self.create_service(AddTwoInts, '/fuzz/add', self.on_add)
        self.create_service(Trigger, '/fuzz/report', self.on_report)
        ActionServer(self, Fibonacci, '/fuzz/fib', self.execute)

    def on_string(self, msg):
        print('heard', msg.data.upper(), flush=True)

    def on_scan(self, msg):
        print('scan', sum(msg.ranges) + msg.range_max, flush=True)

    def on_add(self, request, response):
        response.sum = request.a + request.b
        return response

    def execute(self, goal_handle):
        sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            sequence.append(sequence[i] + sequence[i - 1])
        goal_handle.succeed()
        return Fibonacci.Result(sequence=sequence)

    def on_report(self, request, response):
        response.success = True
        response.message = json.dumps({
            'topics': {s.topic_name: s.rejected for s in self.subs},
            'services': {s.srv_name: s.rejected for s in self.services}})
        return response


zros.init()
node = Target()
print('ready', flush=True)
zros.spin(node)
'''

COUNT = 300          # malformed samples or requests per surface
SEED = 20            # deterministic: a failure reproduces


# -- generators of invalid payloads ----------------------------------------------------------------
def _random_value(rng: random.Random, depth: int = 0):
    """Any MessagePack value: what a confused or hostile client might send."""
    kinds = ['int', 'bigint', 'float', 'nan', 'str', 'bytes', 'bool', 'none', 'ext']
    if depth < 3:
        kinds += ['list', 'list', 'map']
    kind = rng.choice(kinds)
    if kind == 'int':
        return rng.randint(-300, 300)
    if kind == 'bigint':
        return rng.choice([2 ** 63, -2 ** 63 - 1 + 1, 2 ** 64 - 1, 2 ** 31, -2 ** 31 - 1])
    if kind == 'float':
        return rng.choice([0.5, -1e39, 1e300, math.inf])
    if kind == 'nan':
        return math.nan
    if kind == 'str':
        return rng.choice(['', 'x', 'é✓', 'a' * 300])
    if kind == 'bytes':
        return os.urandom(rng.randint(0, 20))
    if kind == 'bool':
        return rng.random() < 0.5
    if kind == 'none':
        return None
    if kind == 'ext':
        return msgpack.ExtType(rng.randint(0, 127), os.urandom(rng.randint(0, 8)))
    if kind == 'map':
        return {str(rng.randint(0, 9)): _random_value(rng, depth + 1) for _ in range(rng.randint(0, 3))}
    return [_random_value(rng, depth + 1) for _ in range(rng.randint(0, 4))]


def _replace_leaf(rng: random.Random, header, wrong):
    """A copy of a header (nested lists) with one leaf replaced by `wrong`."""
    header = json.loads(json.dumps(header))  # deep copy of lists, numbers and strings
    path, node = [], header
    while True:
        index = rng.randrange(len(node))
        path.append(index)
        if isinstance(node[index], list) and node[index]:
            node = node[index]
            continue
        node[index] = wrong
        return header


def malformed(rng: random.Random, valid_header: list, tail: bytes, wrong_leaves: list, is_valid) -> list[bytes]:
    """COUNT payloads that are not valid encodings of the type whose valid payload is
    `valid_header` + `tail`: a mix of garbage, truncations, trailing bytes, random MessagePack
    values, v1-style maps and valid headers with one wrong leaf. `is_valid(payload)` is an
    independent check (written from docs/protocol.md) that screens out accidental hits."""
    valid = msgpack.packb(valid_header) + tail
    out: list[bytes] = []
    while len(out) < COUNT:
        kind = rng.randrange(6)
        if kind == 0:
            payload = os.urandom(rng.randint(0, 64))
        elif kind == 1:
            payload = valid[:rng.randrange(len(valid))]
        elif kind == 2:
            payload = valid + os.urandom(rng.randint(1, 8))
        elif kind == 3:
            payload = msgpack.packb(_random_value(rng))
        elif kind == 4:
            payload = msgpack.packb({'data': _random_value(rng)})
        else:
            payload = msgpack.packb(_replace_leaf(rng, valid_header, rng.choice(wrong_leaves))) + tail
        if not is_valid(payload):
            out.append(payload)
    return out


def _header(payload: bytes):
    """(header, tail) of a payload, or None when it is not MessagePack at all."""
    unpacker = msgpack.Unpacker(strict_map_key=False)
    unpacker.feed(payload)
    try:
        return unpacker.unpack(), payload[unpacker.tell():]
    except Exception:  # noqa: BLE001 - not a MessagePack value
        return None


def _is_int(value, low: int, high: int) -> bool:
    return type(value) is int and low <= value <= high


def valid_string(payload: bytes) -> bool:
    parsed = _header(payload)
    return parsed is not None and not parsed[1] and isinstance(parsed[0], list) and len(parsed[0]) == 1 \
        and type(parsed[0][0]) is str


def valid_add_request(payload: bytes) -> bool:
    parsed = _header(payload)
    return parsed is not None and not parsed[1] and isinstance(parsed[0], list) and len(parsed[0]) == 2 \
        and all(_is_int(v, -2 ** 63, 2 ** 63 - 1) for v in parsed[0])


def valid_names_request(payload: bytes) -> bool:
    parsed = _header(payload)
    return parsed is not None and not parsed[1] and isinstance(parsed[0], list) and len(parsed[0]) == 1 \
        and isinstance(parsed[0][0], list) and all(type(n) is str for n in parsed[0][0])


def valid_scan(payload: bytes) -> bool:
    """Only the shape: every screened-in candidate must fail this, which the generators ensure
    (a 10-field header with the right leaves and a matching tail is the one valid form)."""
    parsed = _header(payload)
    if parsed is None or not isinstance(parsed[0], list) or len(parsed[0]) != 10:
        return False
    header, tail = parsed
    floats = header[1:8]
    stamp_ok = isinstance(header[0], list) and len(header[0]) == 2 and isinstance(header[0][0], list) \
        and len(header[0][0]) == 2 and _is_int(header[0][0][0], -2 ** 31, 2 ** 31 - 1) \
        and _is_int(header[0][0][1], 0, 2 ** 32 - 1) and type(header[0][1]) is str
    floats_ok = all(type(f) in (int, float) and type(f) is not bool
                    and (math.isinf(f) or math.isnan(f) or abs(f) <= 3.4028234663852886e38) for f in floats)
    counts_ok = all(_is_int(c, 0, 2 ** 40) for c in header[8:])
    return stamp_ok and floats_ok and counts_ok and len(tail) == 4 * (header[8] + header[9])


def valid_goal_request(payload: bytes) -> bool:
    """[goal_id [16], goal [order], client_id], then the goal id's 16 bytes."""
    parsed = _header(payload)
    return parsed is not None and len(parsed[1]) == 16 and isinstance(parsed[0], list) and len(parsed[0]) == 3 \
        and parsed[0][0] == [16] and isinstance(parsed[0][1], list) and len(parsed[0][1]) == 1 \
        and _is_int(parsed[0][1][0], -2 ** 31, 2 ** 31 - 1) and type(parsed[0][2]) is str


def valid_uuid_request(payload: bytes) -> bool:
    parsed = _header(payload)
    return parsed is not None and parsed[0] == [[16]] and len(parsed[1]) == 16


WRONG = [None, 'x', b'x', [1], {'a': 1}, True, math.nan, 1e39, -1, 2 ** 64 - 1, msgpack.ExtType(3, b'')]


def _attachment(rng: random.Random, type_name: str, type_hash: str, seq: int) -> bytes | None:
    """None, the right zros attachment, or a wrong one: another type, v1, truncated, random."""
    choice = rng.randrange(6)
    stamp = struct.pack('<Qq', seq, time.time_ns())
    if choice == 0:
        return None
    if choice == 1:
        return b'Z2' + b'\x11' * 16 + stamp + bytes.fromhex(type_hash) + type_name.encode()
    if choice == 2:
        return b'Z2' + b'\x12' * 16 + stamp + bytes.fromhex(Trigger._HASH) + b'std_srvs/srv/Trigger'
    if choice == 3:
        return b'Z1' + b'\x13' * 16 + stamp + bytes.fromhex(type_hash) + type_name.encode()
    if choice == 4:
        return b'Z2' + os.urandom(rng.randint(0, 20))
    return os.urandom(rng.randint(1, 64))


# -- the test ---------------------------------------------------------------------------------------
@pytest.fixture
def target(spawn):
    child = spawn.script(TARGET, name='fuzz_target')
    child.wait_for_output('ready', timeout=15)
    return child


def _report(node: Node) -> dict:
    client = node.create_client(Trigger, '/fuzz/report')
    assert client.wait_for_service(10)
    return json.loads(client.call(Trigger.Request(), timeout_sec=10).message)


def _wait_for_queryable(raw_session, key: str, payload: bytes, timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if list(raw_session.get(key, payload=payload, timeout=1.0)):
            return
        time.sleep(0.05)
    raise AssertionError(f'no queryable answers {key}')


def _request_all(raw_session, key: str, payloads: list[bytes], type_name: str, type_hash: str,
                 rng: random.Random) -> list[str]:
    """Send every request (with a random kind of attachment) and return the error replies."""
    errors = []
    for seq, payload in enumerate(payloads, 1):
        attachment = _attachment(rng, type_name, type_hash, seq)
        extra = {} if attachment is None else {'attachment': attachment}
        replies = list(raw_session.get(key, payload=payload, timeout=5.0, **extra))
        assert len(replies) == 1, f'{key}: {len(replies)} replies to {payload!r:.80}'
        assert replies[0].err is not None, f'{key} accepted {payload!r:.80}'
        errors.append(replies[0].err.payload.to_string())
    return errors


def test_malformed_input_on_every_surface(target, context, raw_session, wait_for):
    rng = random.Random(SEED)
    domain = context.domain_id
    node = Node('fuzz_observer', context=context)
    assert _report(node)['topics'] == {'/fuzz/chatter': 0, '/fuzz/scan': 0}

    # Topics: a String and a LaserScan (header + tail) subscription.
    scan_header = [[[1, 2], 'laser'], 0.0, 1.0, 0.5, 0.0, 0.1, 0.05, 10.0, 2, 1]
    scan_tail = np.array([1.0, 2.0, 3.0], '<f4').tobytes()
    topics = {
        '/fuzz/chatter': (malformed(rng, ['hello'], b'', WRONG, valid_string), String),
        '/fuzz/scan': (malformed(rng, scan_header, scan_tail, WRONG + [2 ** 40], valid_scan), LaserScan),
    }
    for topic, (payloads, msg_type) in topics.items():
        key = f'zros/{domain}/t/{topic[1:]}'
        publisher = raw_session.declare_publisher(key)
        wait_for(lambda: publisher.matching_status.matching, timeout=10)
        for seq, payload in enumerate(payloads, 1):
            attachment = _attachment(rng, msg_type._TYPE, msg_type._HASH, seq)
            publisher.put(payload, **({} if attachment is None else {'attachment': attachment}))
        publisher.undeclare()
    wait_for(lambda: _report(node)['topics'] == {'/fuzz/chatter': COUNT, '/fuzz/scan': COUNT}, timeout=15,
             message=lambda: f'topic rejections {_report(node)["topics"]}\n{target.output()[-2000:]}')

    # Services: AddTwoInts, the action's three services, two parameter services.
    names_payload = msgpack.packb([['speed']])
    services = {
        '/fuzz/add': (msgpack.packb([1, 2]), valid_add_request, AddTwoInts, [0, 1]),
        '/fuzz/fib/_action/send_goal': (msgpack.packb([[16], [5], 'c']) + bytes(16), valid_goal_request, None,
                                        [[16], [3], 'abc']),
        '/fuzz/fib/_action/get_result': (msgpack.packb([[16]]) + bytes(16), valid_uuid_request, None, [[16]]),
        '/fuzz_target/get_parameters': (names_payload, valid_names_request, GetParameters, [['a', 'b']]),
        '/fuzz_target/describe_parameters': (names_payload, valid_names_request, None, [['a']]),
    }
    for name, (probe, is_valid, srv_type, header) in services.items():
        key = f'zros/{domain}/s/{name[1:]}'
        _wait_for_queryable(raw_session, key, probe)
        tail = bytes(16) if header[0] == [16] else b''  # a UUID's 16 bytes
        payloads = malformed(rng, header, tail, WRONG, is_valid)
        type_name, type_hash = (srv_type._TYPE, srv_type._HASH) if srv_type else ('x/srv/Y', '00' * 8)
        errors = _request_all(raw_session, key, payloads, type_name, type_hash, rng)
        assert all('refused the request' in e and '\n' not in e for e in errors), \
            [e for e in errors if 'refused the request' not in e][:3]

    # An oversized parameter request (200k names) is refused unread, and the next call is prompt.
    key = f'zros/{domain}/s/fuzz_target/get_parameters'
    huge = msgpack.packb([['p%d' % i for i in range(200_000)]])
    replies = list(raw_session.get(key, payload=huge, timeout=10.0))
    assert replies[0].err is not None and 'larger than the limit' in replies[0].err.payload.to_string()
    started = time.monotonic()
    replies = list(raw_session.get(key, payload=names_payload, timeout=5.0))
    assert replies[0].ok is not None and time.monotonic() - started < 1.0

    report = _report(node)
    assert report['topics'] == {'/fuzz/chatter': COUNT, '/fuzz/scan': COUNT}
    rejected = report['services']
    for name in ('/fuzz/add', '/fuzz/fib/_action/send_goal', '/fuzz/fib/_action/get_result',
                 '/fuzz_target/describe_parameters'):
        assert rejected[name] == COUNT, (name, rejected)
    assert rejected['/fuzz_target/get_parameters'] == COUNT + 1
    assert rejected['/fuzz/report'] == 0

    # Normal service afterwards, through zros clients and publishers.
    string_pub = node.create_publisher(String, '/fuzz/chatter', 10)
    scan_pub = node.create_publisher(LaserScan, '/fuzz/scan', 10)
    assert string_pub.wait_for_subscribers(1, 10) and scan_pub.wait_for_subscribers(1, 10)
    string_pub.publish(String(data='still here'))
    scan_pub.publish(LaserScan(range_max=1.0, ranges=[2.0, 3.0]))
    target.wait_for_output('heard STILL HERE', timeout=10)
    target.wait_for_output('scan 6.0', timeout=10)
    add = node.create_client(AddTwoInts, '/fuzz/add')
    assert add.call(AddTwoInts.Request(a=40, b=2), timeout_sec=10).sum == 42
    from zros.action import ActionClient
    fib = ActionClient(node, Fibonacci, '/fuzz/fib')
    assert fib.wait_for_server(10)
    result = fib.send_goal(Fibonacci.Goal(order=5))
    assert result.result.sequence.tolist() == [0, 1, 1, 2, 3, 5]
    params = node.create_client(GetParameters, '/fuzz_target/get_parameters')
    assert params.call(GetParameters.Request(names=['speed']), timeout_sec=10).values[0].double_value == 1.5

    output = target.output()
    assert 'Traceback' not in output, output[-3000:]
    assert target.popen.poll() is None, 'the node exited'
    # one error line per topic and sender, not one per sample
    assert output.count("dropping messages on '/fuzz/chatter'") <= 3, output[-3000:]
