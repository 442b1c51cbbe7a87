"""A stranger's client, written from docs/protocol.md alone: plain zenoh-python and msgpack
publish to, subscribe to and call zros nodes. Nothing here imports zros's codec or wire code:
the hashes, attachments and payloads are built from the document's recipes."""
from __future__ import annotations

import hashlib
import os
import struct
import threading
import time

import msgpack
import numpy as np
import pytest

from zros.executors import SingleThreadedExecutor
from zros.node import Node

from interfaces.example_interfaces.srv import AddTwoInts
from interfaces.sensor_msgs.msg import LaserScan
from interfaces.std_msgs.msg import String


# -- the document's recipes ---------------------------------------------------------------------
def doc_hash(text: str) -> str:
    """'The type hash': the first 16 hex digits of SHA-256 of the definition text."""
    return hashlib.sha256(text.encode()).hexdigest()[:16]


TIME = doc_hash('builtin_interfaces/msg/Time;sec:int32;nanosec:uint32')
HEADER = doc_hash(f'std_msgs/msg/Header;stamp:builtin_interfaces/Time@{TIME};frame_id:string')
STRING = doc_hash('std_msgs/msg/String;data:string')
LASER_SCAN = doc_hash(
    f'sensor_msgs/msg/LaserScan;header:std_msgs/Header@{HEADER};angle_min:float32;angle_max:float32;'
    'angle_increment:float32;time_increment:float32;scan_time:float32;range_min:float32;'
    'range_max:float32;ranges:float32[];intensities:float32[]')
ADD_TWO_INTS = doc_hash(doc_hash('example_interfaces/srv/AddTwoInts_Request;a:int64;b:int64') + ';'
                        + doc_hash('example_interfaces/srv/AddTwoInts_Response;sum:int64'))


def attachment(type_name: str, type_hash: str, gid: bytes, seq: int) -> bytes:
    """'Topic samples': magic, gid, sequence (u64 LE), source time (i64 LE), hash, type name."""
    return b'Z2' + gid + struct.pack('<Qq', seq, time.time_ns()) + bytes.fromhex(type_hash) + type_name.encode()


def topic_key(domain: int, topic: str) -> str:
    return f'zros/{domain}/t/{topic.lstrip("/")}'


def service_key(domain: int, name: str) -> str:
    return f'zros/{domain}/s/{name.lstrip("/")}'


# -- zros side ----------------------------------------------------------------------------------
class Spun:
    """A zros node spun by a SingleThreadedExecutor in a background thread."""

    def __init__(self, context, name: str) -> None:
        self.node = Node(name, context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self._spin, daemon=True)

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except Exception:  # noqa: BLE001 - ends when the context shuts down
            pass

    def __enter__(self) -> 'Spun':
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.executor.shutdown()
        self.thread.join(5)


def _wait_for_match(raw_session, key: str, timeout: float = 5.0) -> None:
    """Until the raw session knows a subscriber of `key` (so a put is not lost)."""
    publisher = raw_session.declare_publisher(key)
    deadline = time.monotonic() + timeout
    while not publisher.matching_status.matching and time.monotonic() < deadline:
        time.sleep(0.02)
    publisher.undeclare()


def test_the_documented_hashes_are_the_ones_zros_uses():
    assert (STRING, LASER_SCAN, ADD_TWO_INTS) == (String._HASH, LaserScan._HASH, AddTwoInts._HASH)
    assert STRING == 'bde7214dc1581c71'  # the worked example


def test_raw_publisher_to_zros_subscription(context, raw_session, wait_for, log_records):
    with Spun(context, 'conformance_listener') as spun:
        strings, scans = [], []
        sub = spun.node.create_subscription(String, '/conf/chatter', strings.append, 100)
        scan_sub = spun.node.create_subscription(LaserScan, '/conf/scan', scans.append, 100)
        key, scan_key = topic_key(context.domain_id, '/conf/chatter'), topic_key(context.domain_id, '/conf/scan')
        _wait_for_match(raw_session, key)
        _wait_for_match(raw_session, scan_key)
        gid = os.urandom(16)
        # with an attachment, and without one (the subscription then checks the payload alone)
        raw_session.put(key, msgpack.packb(['with attachment']),
                        attachment=attachment('std_msgs/msg/String', STRING, gid, 1))
        raw_session.put(key, msgpack.packb(['without attachment']))
        # a numeric array: the count in the header, the float32 values in the tail
        header = [[[12, 34], 'laser'], -1.5, 1.5, 0.5, 0.0, 0.1, 0.05, 10.0, 3, 0]
        raw_session.put(scan_key, msgpack.packb(header) + np.array([1.0, 2.0, 3.0], '<f4').tobytes(),
                        attachment=attachment('sensor_msgs/msg/LaserScan', LASER_SCAN, gid, 1))
        wait_for(lambda: len(strings) == 2 and len(scans) == 1, timeout=5,
                 message=lambda: f'strings {strings}, scans {scans}, rejected {sub.rejected} {scan_sub.rejected}')
        assert [m.data for m in strings] == ['with attachment', 'without attachment']
        scan = scans[0]
        assert scan.header.frame_id == 'laser' and scan.header.stamp.sec == 12 and scan.angle_min == -1.5
        assert scan.ranges.tolist() == [1.0, 2.0, 3.0] and len(scan.intensities) == 0

        # Without an attachment the payload is still checked: this is not a std_msgs/String.
        raw_session.put(key, msgpack.packb({'data': 42}))
        raw_session.put(key, msgpack.packb([42]))
        # The same type name with another definition is refused as such.
        raw_session.put(key, msgpack.packb(['other definition']),
                        attachment=attachment('std_msgs/msg/String', doc_hash('std_msgs/msg/String;text:string'),
                                              os.urandom(16), 1))
        wait_for(lambda: sub.rejected == 3, timeout=5, message=lambda: f'rejected {sub.rejected}')
        assert len(strings) == 2
        errors = [text for _, _, text in log_records if 'different definition' in text]
        assert errors and 'std_msgs/msg/String' in errors[0] and 'different String interface files' in errors[0]


def test_zros_publisher_to_raw_subscriber(context, raw_session, wait_for):
    got: dict[str, list] = {'chatter': [], 'scan': []}

    def on(name):
        def callback(sample):
            got[name].append((sample.payload.to_bytes(), sample.attachment.to_bytes()))
        return callback
    subs = [raw_session.declare_subscriber(topic_key(context.domain_id, '/conf/out'), on('chatter')),
            raw_session.declare_subscriber(topic_key(context.domain_id, '/conf/out_scan'), on('scan'))]
    node = Node('conformance_talker', context=context)
    pub = node.create_publisher(String, '/conf/out', 10)
    scan_pub = node.create_publisher(LaserScan, '/conf/out_scan', 10)
    deadline = time.monotonic() + 5
    while not (got['chatter'] and got['scan']) and time.monotonic() < deadline:
        pub.publish(String(data='hello stranger'))
        scan_pub.publish(LaserScan(range_max=5.0, ranges=[0.5, 1.5], intensities=[7.0]))
        time.sleep(0.05)
    for sub in subs:
        sub.undeclare()
    assert got['chatter'] and got['scan']

    payload, att = got['chatter'][0]
    assert msgpack.unpackb(payload) == ['hello stranger']
    assert att[:2] == b'Z2' and att[34:42] == bytes.fromhex(STRING) and att[42:] == b'std_msgs/msg/String'
    sequences = [struct.unpack_from('<Q', a, 18)[0] for _, a in got['chatter']]
    assert sequences == list(range(1, len(sequences) + 1))

    payload, att = got['scan'][0]
    unpacker = msgpack.Unpacker()
    unpacker.feed(payload)
    header, tail = unpacker.unpack(), unpacker.tell()
    assert header[7] == 5.0 and header[8:] == [2, 1]
    values = np.frombuffer(payload, '<f4', count=3, offset=tail)
    assert values.tolist() == [0.5, 1.5, 7.0] and tail + 12 == len(payload)
    assert att[34:42] == bytes.fromhex(LASER_SCAN) and att[42:] == b'sensor_msgs/msg/LaserScan'


@pytest.mark.parametrize('with_attachment', [True, False])
def test_raw_service_client(context, raw_session, wait_for, with_attachment):
    with Spun(context, 'conformance_server') as spun:
        service = spun.node.create_service(AddTwoInts, '/conf/add',
                                           lambda req, resp: setattr(resp, 'sum', req.a + req.b) or resp)
        key = service_key(context.domain_id, '/conf/add')
        gid = os.urandom(16)

        def call(payload: bytes, seq: int):
            extra = {'attachment': attachment('example_interfaces/srv/AddTwoInts', ADD_TWO_INTS, gid, seq)} \
                if with_attachment else {}
            replies = []
            deadline = time.monotonic() + 5
            while not replies and time.monotonic() < deadline:  # until the queryable is known
                replies = list(raw_session.get(key, payload=payload, timeout=2.0, **extra))
            assert len(replies) == 1
            reply = replies[0]
            if reply.ok is not None:
                return msgpack.unpackb(reply.ok.payload.to_bytes())
            return reply.err.payload.to_string()

        assert call(msgpack.packb([2, 3]), 1) == [5]
        assert call(msgpack.packb([-(2 ** 63), 2 ** 63 - 1]), 2) == [-1]
        refused = call(msgpack.packb(['2', 3]), 3)
        assert "service '/conf/add' refused the request" in refused and 'AddTwoInts_Request.a must be an int' in refused
        refused = call(msgpack.packb([2 ** 63, 0]), 4)
        assert 'out of range for int64' in refused
        assert service.rejected == 2
