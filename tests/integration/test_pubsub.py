"""Publish/subscribe over real Zenoh sessions: between processes, many-to-many, reliability,
remapping, transient local, the depth rule, wrong types and corrupt samples, dead nodes."""
from __future__ import annotations

import os
import signal
import struct
import threading
import time

import msgpack
import pytest

from zros.executors import SingleThreadedExecutor
from zros.graph import EntityKind, fetch_entities
from zros.keys import topic_key
from zros.node import Node
from zros.wire import MAGIC as ATTACHMENT_MAGIC, type_tail as attachment_tail
from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile

from interfaces.std_msgs.msg import Int32, String

# A publisher script: `LABEL COUNT RATE_HZ [TOPIC]`; publishes 'LABEL:i' (i from 0) as String
# after at least one subscription matched; COUNT 0 means forever.
LABELLED_PUBLISHER = '''
import sys, time
import zros
from zros.node import Node
from interfaces.std_msgs.msg import String
label, count, rate = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
topic = sys.argv[4] if len(sys.argv) > 4 else '/mm'
with zros.init([]):
    node = Node('pub_' + label)
    pub = node.create_publisher(String, topic, 10)
    pub.wait_for_subscribers(1, 10.0)
    print('matched', flush=True)
    i = 0
    while count == 0 or i < count:
        pub.publish(String(data=f'{label}:{i}'))
        i += 1
        time.sleep(1.0 / rate)
    print('done', flush=True)
'''

# Publishes 'i:padding' for i in 0..N-1 as fast as the reliable publisher allows, once one
# subscription matched.
BURST_PUBLISHER = '''
import sys
import zros
from zros.node import Node
from interfaces.std_msgs.msg import String
count, size = int(sys.argv[1]), int(sys.argv[2])
with zros.init([]):
    node = Node('burst')
    pub = node.create_publisher(String, '/seq', 10)
    if not pub.wait_for_subscribers(1, 10.0):
        sys.exit('no subscription matched')
    padding = 'x' * size
    for i in range(count):
        pub.publish(String(data=f'{i}:{padding}'))
    print('sent', count, flush=True)
    import time; time.sleep(0.5)
'''


def _executor(ctx, *nodes):
    executor = SingleThreadedExecutor(context=ctx)
    for node in nodes:
        executor.add_node(node)
    return executor


# -- between processes ------------------------------------------------------------------------
def test_talker_process_to_in_process_subscription(spawn, context, spin_for):
    talker = spawn.node('demo_nodes', 'talker')
    node = Node('test_listener', context=context)
    received = []
    node.create_subscription(String, '/chatter', received.append, 10)
    executor = _executor(context, node)
    spin_for(executor, lambda: len(received) >= 2, timeout=8,
             message=lambda: f'two messages from the talker; its output:\n{talker.output()}')
    first = int(received[0].data.rsplit(':', 1)[1])
    assert [m.data for m in received[:2]] == [f'Hello World: {first}', f'Hello World: {first + 1}']
    assert isinstance(received[0], String)


def test_in_process_publisher_to_listener_process(spawn, context, wait_for):
    listener = spawn.node('demo_nodes', 'listener')
    node = Node('test_talker', context=context)
    pub = node.create_publisher(String, 'chatter', 10)
    assert pub.wait_for_subscribers(1, 10.0), listener.output()
    count = 0

    def heard() -> bool:
        nonlocal count
        count += 1
        pub.publish(String(data=f'from the test {count}'))
        return 'I heard: [from the test ' in listener.output()
    wait_for(heard, timeout=10, interval=0.05, message=lambda: f'the listener to hear us:\n{listener.output()}')
    assert pub.get_subscription_count() == 1
    listener.wait_for_output(f'I heard: [from the test {count}]', timeout=5)


def test_many_to_many(spawn, make_context, spin_for):
    contexts = [make_context(), make_context()]
    received = [[], []]
    nodes = []
    for i, ctx in enumerate(contexts):
        node = Node(f'sub{i}', context=ctx)
        node.create_subscription(String, '/mm', received[i].append, 100)
        nodes.append(node)
    pubs = [spawn.script(LABELLED_PUBLISHER, label, '0', '50', name=f'pub_{label}') for label in ('A', 'B')]
    for pub in pubs:
        pub.wait_for_output('matched', timeout=10)
    executors = [_executor(ctx, node) for ctx, node in zip(contexts, nodes)]

    def labels(i):
        return {m.data.split(':')[0] for m in received[i]}
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and not all(labels(i) == {'A', 'B'} and len(received[i]) >= 10
                                                  for i in range(2)):
        for executor in executors:
            executor.spin_once(timeout_sec=0.01)
    for i in range(2):
        assert labels(i) == {'A', 'B'}, (i, [m.data for m in received[i]])
        # each publisher's messages arrive in order, none skipped
        for label in 'AB':
            seq = [int(m.data.split(':')[1]) for m in received[i] if m.data.startswith(label)]
            assert seq == list(range(seq[0], seq[0] + len(seq))), (i, label, seq)
    graph = nodes[0].get_topic_names_and_types()
    assert ('/mm', ['std_msgs/msg/String']) in graph
    assert nodes[0].count_publishers('/mm') == 2
    assert nodes[0].count_subscribers('/mm') == 2


@pytest.mark.parametrize('size', [0, 16_000], ids=['small', '16kB'])
def test_reliable_burst_arrives_complete_and_in_order(spawn, context, spin_for, size):
    count = 2000
    node = Node('seq_sub', context=context)
    received = []
    qos = QoSProfile(history=HistoryPolicy.KEEP_ALL)

    def on_message(msg):
        index, padding = msg.data.split(':')
        assert len(padding) == size
        received.append(int(index))
    sub = node.create_subscription(String, '/seq', on_message, qos)
    publisher = spawn.script(BURST_PUBLISHER, str(count), str(size), name='burst')
    executor = _executor(context, node)
    spin_for(executor, lambda: len(received) >= count, timeout=20,
             message=lambda: f'{count} messages, got {len(received)}; publisher:\n{publisher.output()}')
    publisher.wait_for_output(f'sent {count}')
    assert received == list(range(count))
    assert (sub.lost, sub.dropped, sub.rejected) == (0, 0, 0)
    assert sub.received == count


# -- names -------------------------------------------------------------------------------------
def test_remapped_talker_in_namespace(spawn, context, spin_for, wait_for):
    talker = spawn.node('demo_nodes', 'talker', '--ros-args', '-r', 'chatter:=news', '-r', '__ns:=/robot',
                        '-r', '__node:=x')

    def graph():
        return fetch_entities(context.session, context.domain_id)
    entities = wait_for(lambda: [e for e in graph() if e.kind == EntityKind.PUBLISHER and e.name == '/robot/news'],
                        timeout=10, message=lambda: f'/robot/news in the graph; talker:\n{talker.output()}')
    assert entities[0].node_fqn == '/robot/x'
    assert entities[0].type == 'std_msgs/msg/String'
    everything = graph()
    assert '/robot/x' in {e.node_fqn for e in everything if e.kind == EntityKind.NODE}
    assert not any(e.name in ('/chatter', '/robot/chatter') for e in everything)
    assert not any(e.node_fqn in ('/talker', '/robot/talker') for e in everything)

    node = Node('robot_listener', context=context)
    received = []
    node.create_subscription(String, '/robot/news', received.append, 10)
    spin_for(_executor(context, node), lambda: received, timeout=8)
    assert received[0].data.startswith('Hello World: ')
    # the talker's own log uses its remapped name and namespace
    assert '[robot.x]: Publishing:' in talker.output()


# -- QoS ---------------------------------------------------------------------------------------
def test_transient_local_late_joiner_gets_history(make_context, spin_for):
    pub_ctx, sub_ctx = make_context(), make_context()
    qos = QoSProfile(depth=5, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    publisher = Node('latched_pub', context=pub_ctx).create_publisher(String, '/latched', qos)
    for i in range(5):
        publisher.publish(String(data=f'old {i}'))
    time.sleep(0.2)  # nothing is listening: the messages only live in the publisher's cache
    node = Node('late', context=sub_ctx)
    received = []
    node.create_subscription(String, '/latched', received.append, qos)
    executor = _executor(sub_ctx, node)
    spin_for(executor, lambda: len(received) >= 5, timeout=5)
    assert [m.data for m in received] == [f'old {i}' for i in range(5)]
    # and live messages follow the history
    publisher.publish(String(data='new'))
    spin_for(executor, lambda: len(received) >= 6, timeout=5)
    assert [m.data for m in received] == [f'old {i}' for i in range(5)] + ['new']


def test_transient_local_history_is_bounded_by_depth(make_context, spin_for):
    pub_ctx, sub_ctx = make_context(), make_context()
    qos = QoSProfile(depth=3, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    publisher = Node('latched_pub', context=pub_ctx).create_publisher(Int32, '/latched3', qos)
    for i in range(10):
        publisher.publish(Int32(data=i))
    time.sleep(0.2)
    node = Node('late', context=sub_ctx)
    received = []
    node.create_subscription(Int32, '/latched3', lambda m: received.append(m.data), qos)
    executor = _executor(sub_ctx, node)
    spin_for(executor, lambda: len(received) >= 3, timeout=5)
    executor.spin_once(timeout_sec=0.3)
    assert received == [7, 8, 9]


def _spin_a_while(executor, seconds):
    deadline = time.monotonic() + seconds
    while (remaining := deadline - time.monotonic()) > 0:
        executor.spin_once(timeout_sec=remaining)


def _burst_into(sub, publisher, count):
    for i in range(count):
        publisher.publish(Int32(data=i))


@pytest.mark.parametrize('attached', [False, True], ids=['no-executor', 'executor-not-spinning'])
def test_queue_depth_keeps_newest_and_counts_drops(make_context, wait_for, attached):
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('slow', context=sub_ctx)
    received = []
    sub = node.create_subscription(Int32, '/burst', lambda m: received.append(m.data), 5)
    executor = SingleThreadedExecutor(context=sub_ctx)
    if attached:
        executor.add_node(node)
    publisher = Node('fast', context=pub_ctx).create_publisher(Int32, '/burst', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    _burst_into(sub, publisher, 100)
    # every one of the 100 samples reached the subscription: 95 pushed out, 5 waiting
    wait_for(lambda: sub.dropped >= 95, timeout=5, message=lambda: f'95 drops, have {sub.dropped}')
    time.sleep(0.1)
    assert sub.dropped == 95
    assert received == []
    if not attached:
        executor.add_node(node)
    deadline = time.monotonic() + 5.0
    while len(received) < 5 and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    _spin_a_while(executor, 0.2)  # nothing else is waiting
    assert received == [95, 96, 97, 98, 99]
    assert sub.dropped == 95
    assert sub.received == 5
    assert sub.lost == 0  # the depth rule is not network loss
    # the subscription still works normally afterwards
    publisher.publish(Int32(data=1000))
    deadline = time.monotonic() + 5
    while 1000 not in received and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    assert received[-1] == 1000
    assert sub.dropped == 95


@pytest.mark.parametrize('callback_s', [0.0, 0.01], ids=['idle-executor', 'busy-executor'])
def test_a_flood_into_a_spinning_keep_last_queue_is_all_accounted_for(make_context, wait_for, callback_s):
    """A reliable flood into a depth-10 queue while the executor spins: an idle executor is
    handed the full queue before anything is pushed out, a busy one is not waited for. Either
    way every sample is delivered or counted as dropped, newest kept, nothing counted lost."""
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('flooded', context=sub_ctx)
    received = []

    def on_message(msg):
        received.append(msg.data)
        if callback_s:
            time.sleep(callback_s)
    sub = node.create_subscription(Int32, '/flood', on_message, 10)
    executor = SingleThreadedExecutor(context=sub_ctx)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        publisher = Node('flooder', context=pub_ctx).create_publisher(Int32, '/flood', 10)
        assert publisher.wait_for_subscribers(1, 5.0)
        count = 3000
        _burst_into(sub, publisher, count)
        wait_for(lambda: received and received[-1] == count - 1, timeout=10,
                 message=lambda: f'the last sample, have {received[-1:]} ({len(received)} delivered)')
        assert sub.received + sub.dropped == count, (sub.received, sub.dropped)
        assert len(received) == sub.received
        assert received == sorted(set(received))   # in order, none twice
        assert sub.lost == 0
        if callback_s:
            assert sub.dropped > 0   # a 10 ms callback cannot keep up: the flood is not slowed to it
    finally:
        executor.shutdown()
        spinner.join(5)


@pytest.mark.parametrize('depth', [10, 1])
def test_a_flood_does_not_starve_a_timer_of_the_same_executor(make_context, wait_for, depth):
    """spin() drains a flooding KEEP_LAST subscription in batches and waits for its next
    queueful only while nothing else is due: a 20 ms timer beside it keeps firing, and every
    sample is still delivered or counted as dropped."""
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('flooded_with_timer', context=sub_ctx)
    received, ticks = [], []
    sub = node.create_subscription(Int32, '/flood_timer', lambda m: received.append(m.data), depth)
    node.create_timer(0.02, lambda: ticks.append(time.monotonic()))
    executor = _executor(sub_ctx, node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        publisher = Node('flood_timer_pub', context=pub_ctx).create_publisher(Int32, '/flood_timer', 10)
        assert publisher.wait_for_subscribers(1, 5.0)
        start, count = time.monotonic(), 0
        while time.monotonic() - start < 1.0:
            publisher.publish(Int32(data=count))
            count += 1
        flood_ticks = sum(1 for t in ticks if start <= t <= start + 1.0)
        wait_for(lambda: received and received[-1] == count - 1, timeout=10,
                 message=lambda: f'the last sample, have {received[-1:]}')
        assert flood_ticks >= 10, f'the timer fired {flood_ticks} times in a 1 s flood of {count} samples'
        assert sub.received + sub.dropped == count and sub.lost == 0
        assert received == sorted(set(received))
    finally:
        executor.shutdown()
        spinner.join(5)


def test_a_callback_that_raises_mid_burst_loses_nothing(make_context, wait_for):
    """spin() delivers a waiting burst in one go; when the callback raises, the exception
    leaves spin and the samples after it wait for the next spin, in order, none dropped."""
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('fragile', context=sub_ctx)
    received = []

    def on_message(msg):
        received.append(msg.data)
        if msg.data == 4:
            raise ValueError('four')
    sub = node.create_subscription(Int32, '/fragile', on_message, 50)
    executor = _executor(sub_ctx, node)
    publisher = Node('steady', context=pub_ctx).create_publisher(Int32, '/fragile', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    _burst_into(sub, publisher, 20)
    wait_for(lambda: len(sub._queue) == 20, timeout=5, message='the burst waiting in the queue')
    watchdog = threading.Timer(5.0, executor.shutdown)
    watchdog.start()
    try:
        with pytest.raises(ValueError, match='four'):
            executor.spin()
        assert received == [0, 1, 2, 3, 4]
        deadline = time.monotonic() + 5
        while len(received) < 20 and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.1)
    finally:
        watchdog.cancel()
        executor.shutdown()
    assert received == list(range(20))
    assert (sub.received, sub.dropped, sub.lost) == (20, 0, 0)


@pytest.mark.parametrize('pulled', [False, True], ids=['pump', 'pull'])
def test_samples_waiting_behind_a_running_callback_keep_only_the_newest(make_context, wait_for, pulled):
    """While spin() runs the callback for the first sample of a waiting burst, `depth` newer
    samples arrive: the rest of the burst is pushed out by the KEEP_LAST rule and counted in
    `dropped`, not `lost`, although spin() had taken it in one batch with the first. With a
    second subscription the newer samples reach the queue through the subscription's pump
    while the callback runs; with this one alone spin() receives from the channel itself (the
    pull) and they wait there, to be queued when the callback has taken longer than the
    executor's hand-off wait (2 ms): the same deliveries either way."""
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('overtaken', context=sub_ctx)
    publisher = Node('bursty', context=pub_ctx).create_publisher(Int32, '/overtaken', 10)
    received = []

    def on_message(msg):
        received.append(msg.data)
        if msg.data == 0:
            for i in (3, 4, 5):
                publisher.publish(Int32(data=i))
            # (1 and 2 are in the executor's batch; the newer three wait behind them, so the
            # batch's two are overtaken: dropped when the executor moves on)
            if pulled:
                time.sleep(0.3)
            else:
                wait_for(lambda: len(sub._queue) == 3, timeout=5, message='three newer samples waiting')
    sub = node.create_subscription(Int32, '/overtaken', on_message, 3)
    if not pulled:
        node.create_subscription(Int32, '/overtaken_idle', lambda m: None, 3)
    assert publisher.wait_for_subscribers(1, 5.0)
    for i in (0, 1, 2):
        publisher.publish(Int32(data=i))
    wait_for(lambda: len(sub._queue) == 3, timeout=5, message='the burst waiting in the queue')
    executor = _executor(sub_ctx, node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        wait_for(lambda: len(received) == 4, timeout=5, message=lambda: f'4 deliveries, have {received}')
        time.sleep(0.2)
        assert (executor._pull_sub is sub) is pulled
    finally:
        executor.shutdown()
        spinner.join(5)
    assert received == [0, 3, 4, 5]
    assert (sub.received, sub.dropped, sub.lost) == (4, 2, 0)


def test_losses_are_counted_across_the_samples_the_depth_rule_pushed_out(make_context, wait_for):
    """Samples pushed out by KEEP_LAST are queued undecoded and read only by the executor: a
    network loss among them still counts in `lost` (the depth rule's drops do not), for plain
    and MessageInfo callbacks, and a stretch too long to keep notes of counts no false loss."""
    from collections import deque
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('slow', context=sub_ctx)
    plain, with_info = [], []
    subs = [node.create_subscription(Int32, '/lossy', lambda m: plain.append(m.data), 5),
            node.create_subscription(Int32, '/lossy', lambda m, info: with_info.append(m.data), 5)]
    long_gap = node.create_subscription(Int32, '/lossy', lambda m: None, 5)
    long_gap._evicted = deque(maxlen=3)  # notes of only 3 pushed-out samples are kept
    publisher = Node('fast', context=pub_ctx).create_publisher(Int32, '/lossy', 10)
    assert publisher.wait_for_subscribers(3, 5.0)
    put, sent = publisher._put, [0]

    def lossy(payload, **kwargs):  # the network loses the 30th and the 80th sample
        sent[0] += 1
        if sent[0] not in (30, 80):
            put(payload, **kwargs)
    publisher._put = lossy
    for i in range(100):
        publisher.publish(Int32(data=i))
    wait_for(lambda: all(s.dropped == 93 for s in subs + [long_gap]), timeout=5,
             message=lambda: f'93 drops each, have {[s.dropped for s in subs + [long_gap]]}')
    assert [s.lost for s in subs] == [0, 0]  # nothing is read before the executor runs
    executor = SingleThreadedExecutor(context=sub_ctx)
    executor.add_node(node)
    wait_for(lambda: (executor.spin_once(timeout_sec=0.05), len(plain) == len(with_info) == 5)[1], timeout=5)
    assert plain == with_info == [95, 96, 97, 98, 99]
    assert [(s.lost, s.dropped, s.received) for s in subs] == [(2, 93, 5)] * 2
    assert long_gap.lost == 0   # its notes start after the losses: it saw no gap


# -- wrong and broken samples ---------------------------------------------------------------
def _dropping_errors(records):
    return [r for r in records if r[0] >= 40 and 'dropping messages' in r[2]]


def test_wrong_type_is_rejected_and_logged_once(make_context, spin_for, log_records):
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('typed', context=sub_ctx)
    received = []
    sub = node.create_subscription(String, '/mixed', received.append, 100)
    executor = _executor(sub_ctx, node)
    pub_node = Node('int_pub', context=pub_ctx)
    wrong = pub_node.create_publisher(Int32, '/mixed', 10)
    assert wrong.wait_for_subscribers(1, 5.0)
    for i in range(5):
        wrong.publish(Int32(data=i))
    spin_for(executor, lambda: sub.rejected >= 5, timeout=5)
    assert received == []
    errors = _dropping_errors(log_records)
    assert len(errors) == 1, errors
    assert 'std_msgs/msg/Int32' in errors[0][2] and 'std_msgs/msg/String' in errors[0][2]
    assert "'/mixed'" in errors[0][2]
    # the subscriber is alive: a message of the right type still arrives
    right = pub_node.create_publisher(String, '/mixed', 10)
    assert right.wait_for_subscribers(1, 5.0)
    right.publish(String(data='right'))
    spin_for(executor, lambda: received, timeout=5)
    assert [m.data for m in received] == ['right']
    assert sub.rejected == 5
    assert len(_dropping_errors(log_records)) == 1


def _forged_attachment(msg_type, seq=1, gid=b'\x07' * 16):
    return ATTACHMENT_MAGIC + gid + struct.pack('<Qq', seq, time.time_ns()) + attachment_tail(msg_type)


def test_corrupt_payloads_do_not_kill_the_subscriber(make_context, spin_for, log_records):
    raw_ctx, sub_ctx = make_context(), make_context()
    node = Node('robust', context=sub_ctx)
    received = []
    sub = node.create_subscription(String, '/corrupt', received.append, 100)
    executor = _executor(sub_ctx, node)
    key = topic_key(raw_ctx.domain_id, '/corrupt')
    # let the raw session learn about the subscription before putting
    Node('observer', context=raw_ctx).context.graph.wait_for(
        lambda es: any(e.kind == EntityKind.SUBSCRIPTION and e.name == '/corrupt' for e in es), 5.0)
    session = raw_ctx.session
    bad = [
        (b'garbage', None),                                              # no attachment, not msgpack
        (b'\xc1', None),                                                 # reserved msgpack byte
        (msgpack.packb([1, 2, 3]), None),                                # msgpack, wrong shape
        (msgpack.packb({'data': 'x'}), None),                            # a map (protocol v1's form)
        (msgpack.packb([42]), None),                                     # the right shape, an int for a str
        (b'garbage', _forged_attachment(String, 1)),                     # right type, broken payload
        (msgpack.packb([['x']]), _forged_attachment(String, 2)),         # right type, a list for a str
        (b'', _forged_attachment(String, 3)),                            # empty payload
        (b'garbage', b'Z1'),                                             # truncated attachment
        (b'garbage', os.urandom(64)),                                    # random attachment
    ]
    for payload, attachment in bad:
        if attachment is None:
            session.put(key, payload)
        else:
            session.put(key, payload, attachment=attachment)
    spin_for(executor, lambda: sub.rejected >= len(bad), timeout=5,
             message=lambda: f'{len(bad)} rejections, have {sub.rejected}')
    assert received == []
    assert all('payload is not a valid std_msgs/msg/String' in r[2] or 'sends' in r[2]
               for r in _dropping_errors(log_records))
    # a well-formed sample with a forged (but consistent) attachment is accepted
    session.put(key, msgpack.packb(['raw but fine']), attachment=_forged_attachment(String, 4))
    spin_for(executor, lambda: received, timeout=5)
    assert received[0].data == 'raw but fine'
    # and a real publisher still gets through
    publisher = Node('good', context=raw_ctx).create_publisher(String, '/corrupt', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    publisher.publish(String(data='good'))
    spin_for(executor, lambda: len(received) >= 2, timeout=5)
    assert received[1].data == 'good'
    assert sub.rejected == len(bad)


# -- dead nodes --------------------------------------------------------------------------------
def test_killed_node_leaves_the_graph_within_a_second(spawn, context, wait_for, zros_cli):
    talker = spawn.node('demo_nodes', 'talker')

    def talker_entities():
        return [e for e in fetch_entities(context.session, context.domain_id, timeout=0.5)
                if e.node_fqn == '/talker']
    wait_for(lambda: {e.kind for e in talker_entities()} >= {EntityKind.NODE, EntityKind.PUBLISHER},
                       timeout=10, message=lambda: f'the talker and its publisher in the graph:\n{talker.output()}')
    graph = context.graph  # the live graph of this process
    assert graph.wait_for(lambda es: any(e.node_fqn == '/talker' for e in es), 5.0)
    os.kill(talker.pid, signal.SIGKILL)
    start = time.monotonic()
    assert graph.wait_for(lambda es: not any(e.node_fqn == '/talker' for e in es), 1.0), \
        'the live graph still lists /talker 1 s after SIGKILL'
    assert not talker_entities()
    assert time.monotonic() - start < 1.0
    assert talker.wait(5) == -signal.SIGKILL
    listing = zros_cli('node', 'list')
    assert listing.returncode == 0 and '/talker' not in listing.stdout, listing


def test_killed_hub_process_leaves_the_graph(spawn, wait_for, make_context, zros_cli):
    talker = spawn.node('demo_nodes', 'talker')  # started first: it binds the hub port
    talker.wait_for_output('Publishing:', timeout=10)
    context = make_context()
    assert not context.is_hub
    Node('survivor', context=context)
    graph = context.graph
    assert graph.wait_for(lambda es: any(e.node_fqn == '/talker' for e in es), 5.0)
    os.kill(talker.pid, signal.SIGKILL)
    assert graph.wait_for(lambda es: not any(e.node_fqn == '/talker' for e in es), 1.0)
    assert not [e for e in fetch_entities(context.session, context.domain_id, timeout=0.5)
                if e.node_fqn == '/talker']
    # a fresh process takes the hub port over and sees the surviving node (the survivor
    # re-dials the hub port every 0.2 s; one retry allowed for a heavily loaded machine)
    attempts = []

    def listed():
        attempts.append(zros_cli('node', 'list'))
        assert attempts[-1].returncode == 0, attempts[-1]
        return attempts[-1].stdout.splitlines() == ['/survivor']
    wait_for(listed, timeout=2.0, interval=0, message=lambda: f'/survivor in zros node list: {attempts}')


def test_own_entities_are_in_the_graph_at_once(context):
    node = Node('self_aware', context=context)
    assert node.count_subscribers('/own') == 0  # the graph is running
    release = threading.Event()
    context.graph.add_listener(lambda: release.wait(0.5))  # keeps Zenoh's callback thread busy
    try:
        node.create_publisher(String, '/own', 10)
        node.create_subscription(String, '/own', lambda m: None, 10)
        counts = (node.count_publishers('/own'), node.count_subscribers('/own'))
    finally:
        release.set()
    assert counts == (1, 1)


def test_drops_and_losses_are_visible_in_topic_info(make_context, zros_cli, wait_for):
    """docs/architecture.md §6: nothing is lost silently; `zros topic info -v` shows each
    subscription's counters."""
    pub_ctx, sub_ctx = make_context(), make_context()
    publisher = Node('burster', context=pub_ctx).create_publisher(String, '/burst', 100)
    listener = Node('slow_reader', context=sub_ctx)
    subscription = listener.create_subscription(String, '/burst', lambda m: None, 5)
    wait_for(lambda: publisher.get_subscription_count() == 1, timeout=5)
    for i in range(100):
        publisher.publish(String(data=str(i)))
    wait_for(lambda: subscription.dropped == 95, timeout=5, message=lambda: f'dropped={subscription.dropped}')
    info = zros_cli('topic', 'info', '/burst', '-v')
    assert info.returncode == 0, info
    assert 'Dropped (queue depth full): 95' in info.stdout
    assert 'Lost (gaps in publisher sequence): 0' in info.stdout
    as_json = zros_cli('topic', 'info', '/burst', '--json')
    import json
    assert json.loads(as_json.stdout)['subscriptions'][0]['dropped'] == 95
