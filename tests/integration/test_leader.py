"""Leader/follower over real Zenoh sessions (zros.executors, docs/architecture.md §3): a sample
that arrives while spin() waits runs at once on the thread it arrived on; what rclpy code relies
on still holds: one callback at a time, groups shared with timers, spin_once's one callback,
reliable samples in order and none lost, KEEP_LAST's drops counted, errors out of spin()."""
from __future__ import annotations

import threading
import time

import pytest

from zros import executors
from zros.callback_groups import MutuallyExclusiveCallbackGroup
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.qos import HistoryPolicy, QoSProfile
from zros.task import Future

from conftest import int32_pair, spinning

from interfaces.std_msgs.msg import Int32

KEEP_ALL = QoSProfile(history=HistoryPolicy.KEEP_ALL)


@pytest.fixture(autouse=True)
def _leading(monkeypatch):
    """Leader/follower is opt-in (ZROS_CALLBACK_THREAD=zenoh); these tests hold it on whatever the environment says."""
    monkeypatch.setattr(executors, '_LEADING_ALLOWED', True)


def _pair(make_context, topic, callback, qos=10, group=None):
    """(publisher, subscription, its node, a SingleThreadedExecutor with the node), matched."""
    publisher, sub, node, executor = int32_pair(make_context, topic, callback, qos, group, name='led')
    # A second, idle subscription: with one alone, spin() receives from its channel itself (the
    # pull, tests/integration/test_pull.py), and nothing is led.
    node.create_subscription(Int32, f'{topic}_idle', lambda m: None, 10)
    return publisher, sub, node, executor


_spinning = spinning


@pytest.mark.parametrize('allowed', [True, False], ids=['ZROS_CALLBACK_THREAD=zenoh', 'ZROS_CALLBACK_THREAD=spin'])
def test_which_thread_runs_a_callback_while_spin_waits(make_context, wait_for, monkeypatch, allowed):
    monkeypatch.setattr(executors, '_LEADING_ALLOWED', allowed)
    threads = []
    publisher, _, _, executor = _pair(make_context, '/which', lambda m: threads.append(threading.current_thread()))
    spinner = _spinning(executor)
    try:
        time.sleep(0.2)   # parked
        publisher.publish(Int32(data=1))
        wait_for(lambda: threads, message='the callback')
    finally:
        executor.shutdown()
        spinner.join(5)
    assert (threads[0] is spinner) is not allowed


def test_reliable_samples_arrive_in_order_and_none_is_lost(make_context, wait_for):
    received = []
    publisher, sub, _, executor = _pair(make_context, '/ordered', lambda m: received.append(m.data), KEEP_ALL)
    spinner = _spinning(executor)
    try:
        for i in range(3000):
            publisher.publish(Int32(data=i))
            if i % 500 == 0:
                time.sleep(0.01)   # let the executor park now and then: both paths take part
        wait_for(lambda: len(received) == 3000, timeout=20, message=lambda: f'3000, have {len(received)}')
    finally:
        executor.shutdown()
        spinner.join(5)
    assert received == list(range(3000))
    assert (sub.lost, sub.dropped) == (0, 0)


def test_a_flood_takes_the_hand_off_and_paced_samples_are_led(make_context, wait_for):
    """Leading only after a quiet spell: samples published back to back mostly run on the
    spinning thread (Zenoh's thread receives the next meanwhile), samples 20 ms apart on the
    thread they arrived on; none lost, in order, either way."""
    received = []
    publisher, sub, _, executor = _pair(
        make_context, '/flood_then_paced', lambda m: received.append((m.data, threading.current_thread())), KEEP_ALL)
    spinner = _spinning(executor)
    try:
        time.sleep(0.2)   # parked
        flood = 3000
        for i in range(flood):
            publisher.publish(Int32(data=i))
        wait_for(lambda: len(received) == flood, timeout=20, message=lambda: f'{flood}, have {len(received)}')
        for i in range(flood, flood + 10):
            time.sleep(0.02)
            publisher.publish(Int32(data=i))
        wait_for(lambda: len(received) == flood + 10, timeout=10, message=lambda: f'{flood + 10}, have {len(received)}')
    finally:
        executor.shutdown()
        spinner.join(5)
    assert [data for data, _ in received] == list(range(flood + 10))
    assert (sub.lost, sub.dropped) == (0, 0)
    on_spinner = sum(thread is spinner for _, thread in received[:flood])
    assert on_spinner > flood // 2, f'{on_spinner} of the flood ran on the spinning thread'
    assert not any(thread is spinner for _, thread in received[flood:])


def test_a_timer_in_the_subscriptions_group_never_overlaps_a_led_callback(make_context, wait_for):
    group = MutuallyExclusiveCallbackGroup()
    running, overlaps, ticks, received = [], [], [], []

    def exclusive(record):
        overlaps.append(bool(running))
        running.append(1)
        time.sleep(0.0005)
        running.pop()
        record.append(1)

    publisher, _, node, executor = _pair(make_context, '/shared_group', lambda m: exclusive(received),
                                         KEEP_ALL, group)
    node.create_timer(0.001, lambda: exclusive(ticks), callback_group=group)
    spinner = _spinning(executor)
    try:
        for i in range(400):
            publisher.publish(Int32(data=i))
            time.sleep(0.0005)
        wait_for(lambda: len(received) == 400, timeout=20, message=lambda: f'400, have {len(received)}')
    finally:
        executor.shutdown()
        spinner.join(5)
    assert ticks
    assert not any(overlaps)


def test_spin_once_runs_one_callback_on_the_calling_thread(make_context, wait_for):
    received = []
    publisher, sub, _, executor = _pair(make_context, '/once', lambda m: received.append(
        (m.data, threading.current_thread())), KEEP_ALL)
    for i in range(3):
        publisher.publish(Int32(data=i))
    wait_for(lambda: len(sub._queue) == 3, message='three samples waiting')
    executor.spin_once(timeout_sec=2)
    assert received == [(0, threading.current_thread())]
    publisher.publish(Int32(data=3))   # arrives while nobody spins: waits for the next spin_once
    time.sleep(0.1)
    assert len(received) == 1
    for _ in range(3):
        executor.spin_once(timeout_sec=2)
    assert [data for data, _ in received] == [0, 1, 2, 3]
    executor.shutdown()


def test_spin_until_future_complete_returns_when_a_led_callback_completes_it(make_context):
    done = Future()
    publisher, _, _, executor = _pair(make_context, '/completes', lambda m: done.set_result(m.data))
    result = []

    def spin():
        executor.spin_until_future_complete(done, timeout_sec=10)
        result.append(time.monotonic())
    spinner = _spinning(executor, spin)
    time.sleep(0.2)
    sent = time.monotonic()
    publisher.publish(Int32(data=7))
    spinner.join(10)
    executor.shutdown()
    assert done.result() == 7
    assert result and result[0] - sent < 1.0   # woken by the completion, not by a timeout


def test_an_exception_in_a_led_callback_leaves_spin_on_the_spinning_thread(make_context, wait_for):
    received = []

    def fragile(msg):
        received.append(msg.data)
        if msg.data == 1:
            raise ValueError('one')
    publisher, _, _, executor = _pair(make_context, '/fragile_led', fragile, KEEP_ALL)
    raised = []
    spinner = _spinning(executor, errors=raised)
    time.sleep(0.2)
    publisher.publish(Int32(data=1))
    spinner.join(5)
    assert [str(exc) for exc in raised] == ['one']
    publisher.publish(Int32(data=2))   # the next spin delivers what came after
    spinner = _spinning(executor)
    try:
        wait_for(lambda: received == [1, 2], message=lambda: f'[1, 2], have {received}')
    finally:
        executor.shutdown()
        spinner.join(5)


def test_a_slow_callback_takes_the_hand_off_so_keep_last_drops_and_counts(make_context, wait_for):
    """A callback too slow to run on Zenoh's thread: the flood is not slowed to it, the
    depth-10 queue drops by the QoS rule and every sample is delivered or counted."""
    received = []

    def slow(msg):
        received.append(msg.data)
        time.sleep(0.01)
    publisher, sub, _, executor = _pair(make_context, '/slow_led', slow)
    spinner = _spinning(executor)
    try:
        count = 2000
        started = time.monotonic()
        for i in range(count):
            publisher.publish(Int32(data=i))
        published_in = time.monotonic() - started
        wait_for(lambda: received and received[-1] == count - 1, timeout=10,
                 message=lambda: f'the last sample, have {received[-1:]}')
    finally:
        executor.shutdown()
        spinner.join(5)
    assert published_in < 5   # at 10 ms a callback, 2000 samples would take 20 s
    assert sub.dropped > 0
    assert sub.received + sub.dropped == count
    assert received == sorted(set(received))
    assert sub.lost == 0


def test_shutdown_from_inside_a_led_callback_does_not_wait_for_itself(make_context):
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('stopper', context=sub_ctx)
    stopped = []

    def stop(msg):
        started = time.monotonic()
        sub_ctx.shutdown()
        stopped.append(time.monotonic() - started)
    node.create_subscription(Int32, '/stop_led', stop, 10)
    executor = SingleThreadedExecutor(context=sub_ctx)
    executor.add_node(node)
    publisher = Node('stop_pub', context=pub_ctx).create_publisher(Int32, '/stop_led', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    spinner = _spinning(executor, lambda: _quiet_spin(executor))
    time.sleep(0.2)
    publisher.publish(Int32(data=1))
    spinner.join(10)
    assert not spinner.is_alive()
    assert stopped and stopped[0] < 2.0


def _quiet_spin(executor):
    try:
        executor.spin()
    except executors.ExternalShutdownException:
        pass


def test_a_led_callback_may_destroy_its_own_subscription(make_context, wait_for):
    """A one-shot subscription (rclpy code destroys it in its own callback) run on the Zenoh
    thread that delivers to it: undeclaring from that thread neither hangs nor stops the spin."""
    done = []

    def once(msg):
        done.append(threading.current_thread())
        node.destroy_subscription(sub)
        done.append('destroyed')
    publisher, sub, node, executor = _pair(make_context, '/one_shot', once)
    ticks = []
    spinner = _spinning(executor)
    try:
        time.sleep(0.2)   # parked
        publisher.publish(Int32(data=1))
        wait_for(lambda: len(done) == 2, timeout=5, message='the one-shot callback to end')
        node.create_timer(0.01, lambda: ticks.append(1))
        wait_for(lambda: len(ticks) > 3, timeout=5, message='the spin to go on')
    finally:
        executor.shutdown()
        spinner.join(5)
    assert done[0] is not spinner
    assert sub not in node.subscriptions
