"""Large arrays between processes: through shared memory on one machine, through the network
when a side has no shared memory, bit-exact either way, and independent of Zenoh's buffers
once received (the publisher's pool is small, so its buffers are reused while the test holds
the messages it got)."""
from __future__ import annotations

import hashlib
import json

import numpy as np

from conftest import REPO
from zros.executors import SingleThreadedExecutor
from zros.keys import topic_key
from zros.node import Node

from interfaces.sensor_msgs.msg import Image

COUNT = 12
SIZE = 4 << 20

PUBLISHER = f'''
import sys, time
import numpy as np
import zros
from zros.node import Node
from interfaces.sensor_msgs.msg import Image

zros.init([])
node = Node('big_publisher')
pub = node.create_publisher(Image, '/big', 20)
if not pub.wait_for_subscribers(1, 15):
    sys.exit('no subscriber')
time.sleep(0.5)
for i in range(1, {COUNT} + 1):
    msg = Image(height=1024, width=1024, encoding='rgba8', step=4096,
                data=np.random.default_rng(i).integers(0, 256, {SIZE}, dtype=np.uint8))
    msg.header.stamp.sec = i
    pub.publish(msg)
    time.sleep(0.02)
print('sent', flush=True)
time.sleep(30)
'''


def expected_digest(i: int) -> str:
    return hashlib.sha256(np.random.default_rng(i).integers(0, 256, SIZE, dtype=np.uint8).tobytes()).hexdigest()


def _receive(context, spawn, wait_for, raw_session):
    """Start the publisher (16 MiB pool: four frames) and collect what a zros subscription of
    `context` and a raw Zenoh subscriber of `raw_session` get."""
    raw: list[bool] = []
    if raw_session is not None:
        raw_sub = raw_session.declare_subscriber(topic_key(context.domain_id, '/big'),
                                                 lambda sample: raw.append(sample.payload.as_shm() is not None))
    node = Node('big_subscriber', context=context)
    received: list = []
    node.create_subscription(Image, '/big', received.append, COUNT)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    publisher = spawn.script(PUBLISHER, name='big_publisher')
    wanted_raw = COUNT if raw_session is not None else 0
    wait_for(lambda: (executor.spin_once(0.05), len(received) == COUNT and len(raw) == wanted_raw)[1], timeout=30,
             message=lambda: f'{len(received)} zros and {len(raw)} raw of {COUNT}:\n{publisher.output()}')
    if raw_session is not None:
        raw_sub.undeclare()
    return received, raw


def _check(received) -> None:
    """Digests computed only now, after every frame arrived: a message that still pointed into a
    reused shared-memory buffer would show a later frame's pixels."""
    assert [m.header.stamp.sec for m in received] == list(range(1, COUNT + 1))
    assert [hashlib.sha256(m.data).hexdigest() for m in received] == [expected_digest(i) for i in range(1, COUNT + 1)]
    assert all(len(m.data) == SIZE and m.data.typecode == 'B' for m in received)


def test_large_arrays_through_shared_memory(monkeypatch, spawn, context, raw_session, wait_for):
    monkeypatch.setenv('ZROS_SHM_POOL_SIZE', '16M')  # the publisher's: its buffers are reused
    received, raw = _receive(context, spawn, wait_for, raw_session)
    _check(received)
    # Zenoh sets its pool up on the first large put, which goes the ordinary way
    assert all(raw[1:]), f'payloads in shared memory: {raw}'


def test_a_subscriber_without_shared_memory_still_receives(monkeypatch, spawn, make_context, wait_for):
    monkeypatch.setenv('ZROS_SHM_POOL_SIZE', '0')   # this process: no shared memory at all
    context = make_context()
    monkeypatch.setenv('ZROS_SHM_POOL_SIZE', '16M')  # the publisher has it
    received, _ = _receive(context, spawn, wait_for, None)
    _check(received)


def test_shared_memory_settings(monkeypatch):
    from zros.config import SessionSettings, build_config
    monkeypatch.setenv('ZROS_SHM_POOL_SIZE', '0')
    config = build_config(SessionSettings(), as_hub=False)
    assert json.loads(config.get_json('transport/shared_memory/enabled')) is False
    # with a config file (the robot's client.json5) too: the variable wins over Zenoh's default
    config = build_config(SessionSettings(config_file=str(REPO / 'configs' / 'zenoh' / 'client.json5')), as_hub=False)
    assert json.loads(config.get_json('transport/shared_memory/enabled')) is False
    monkeypatch.setenv('ZROS_SHM_POOL_SIZE', '128M')
    config = build_config(SessionSettings(), as_hub=False)
    assert json.loads(config.get_json('transport/shared_memory/transport_optimization/pool_size')) == 128 << 20
    monkeypatch.delenv('ZROS_SHM_POOL_SIZE')
    config = build_config(SessionSettings(), as_hub=False)
    assert json.loads(config.get_json('transport/shared_memory/transport_optimization/pool_size')) == 64 << 20



FLOOD_PUBLISHER = '''
import sys, time
import zros
from zros.node import Node
from interfaces.sensor_msgs.msg import Image

zros.init([])
node = Node('flood_publisher')
pub = node.create_publisher(Image, '/flood64k', 10)
if not pub.wait_for_subscribers(1, 15):
    sys.exit('no subscriber')
msg = Image(height=256, width=256, encoding='mono8', step=256, data=bytes(65536))
count, end = 0, time.monotonic() + 2.0
while time.monotonic() < end:
    msg.header.stamp.sec = count
    pub.publish(msg)
    count += 1
print('sent', count, flush=True)
time.sleep(30)   # its pool goes with the process: messages still in flight would go with it
'''


def test_a_flood_through_shared_memory_loses_nothing(monkeypatch, spawn, context, wait_for):
    """2 s of 64 KiB messages as fast as a publisher can, into a depth-10 subscription that
    keeps up only in part: every message is delivered or counted as dropped by the depth rule,
    none lost. (Buffers of a pool of zros's own were garbage-collected while they still waited
    in the socket, and a reliable stream lost hundreds.)"""
    import re
    import threading
    monkeypatch.setenv('ZROS_SHM_POOL_SIZE', '256M')   # the publisher's, as for a camera pipeline
    node = Node('flood_subscriber', context=context)
    got: list[int] = []
    sub = node.create_subscription(Image, '/flood64k', lambda msg: got.append(msg.header.stamp.sec), 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        publisher = spawn.script(FLOOD_PUBLISHER, name='flood_publisher')
        sent = wait_for(lambda: re.search(r'^sent (\d+)$', publisher.output(), re.M), timeout=30,
                        message=lambda: publisher.output())
        count = int(sent.group(1))
        wait_for(lambda: got and got[-1] == count - 1, timeout=20,
                 message=lambda: f'the last message ({count - 1}), have {got[-1:]}; lost {sub.lost}')
        assert sub.lost == 0, f'{sub.lost} of {count} lost'
        assert sub.received + sub.dropped == count
        assert got == sorted(set(got))
    finally:
        executor.shutdown()
        spinner.join(5)
