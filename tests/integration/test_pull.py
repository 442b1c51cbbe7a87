"""The pull (zros.executors, docs/architecture.md §3): an executor whose nodes have one
subscription and no timer receives from that subscription's Zenoh channel on the spinning thread
itself. What rclpy code relies on still holds, over real Zenoh sessions: callbacks on the
spinning thread, reliable samples in order and none lost, other work (services, guard
conditions, tasks, futures, shutdown) still wakes the spin, and a change of the node's entities
hands the channel back to the subscription's pump."""
from __future__ import annotations

import threading
import time

import pytest

from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.qos import HistoryPolicy, QoSProfile
from zros.task import Future

from conftest import int32_pair, spinning

from interfaces.std_msgs.msg import Int32
from interfaces.std_srvs.srv import Trigger

KEEP_ALL = QoSProfile(history=HistoryPolicy.KEEP_ALL)


def _pair(make_context, topic, callback, qos=10):
    return int32_pair(make_context, topic, callback, qos, name='pulled')


_spinning = spinning


def _stop(executor, spinner):
    executor.shutdown()
    spinner.join(5)
    assert not spinner.is_alive()


def test_a_lone_subscription_is_pulled_on_the_spinning_thread_in_order_and_complete(make_context, wait_for):
    received, threads = [], set()

    def on_message(msg):
        received.append(msg.data)
        threads.add(threading.current_thread())
    publisher, sub, _, executor = _pair(make_context, '/pulled', on_message, KEEP_ALL)
    spinner = _spinning(executor)
    try:
        wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
        for i in range(3000):
            publisher.publish(Int32(data=i))
            if i % 500 == 0:
                time.sleep(0.01)   # let the spin block on the channel now and then
        wait_for(lambda: len(received) == 3000, timeout=20, message=lambda: f'3000, have {len(received)}')
    finally:
        _stop(executor, spinner)
    assert received == list(range(3000))
    assert (sub.lost, sub.dropped) == (0, 0)
    assert threads == {spinner}


def test_services_guard_conditions_and_tasks_wake_a_pulling_spin(make_context, wait_for):
    publisher, sub, node, executor = _pair(make_context, '/pulled_wake', lambda m: None)
    served, guarded, tasked = [], [], []

    def on_trigger(request, response):
        served.append(threading.current_thread())
        response.success = True
        return response
    node.create_service(Trigger, '/pulled_trigger', on_trigger)
    guard = node.create_guard_condition(lambda: guarded.append(threading.current_thread()))
    spinner = _spinning(executor)
    try:
        wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
        client_node = Node('pull_client', context=make_context())
        client = client_node.create_client(Trigger, '/pulled_trigger')
        assert client.wait_for_service(5.0)
        future = client.call_async(Trigger.Request())
        wait_for(future.done, message='the service reply')
        assert future.result().success
        guard.trigger()
        wait_for(lambda: guarded, message='the guard condition callback')
        executor.create_task(lambda: tasked.append(threading.current_thread()))
        wait_for(lambda: tasked, message='the task')
        assert executor._pull_sub is sub   # (still pulling: none of these changes the candidate)
    finally:
        _stop(executor, spinner)
    assert served == guarded == tasked == [spinner]


def test_a_timer_or_a_second_subscription_hands_the_channel_back(make_context, wait_for):
    received, ticks, second = [], [], []
    publisher, sub, node, executor = _pair(make_context, '/pulled_then_not', lambda m: received.append(m.data))
    spinner = _spinning(executor)
    try:
        wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
        timer = node.create_timer(0.01, lambda: ticks.append(1))   # from another thread
        wait_for(lambda: len(ticks) >= 3, message='the timer firing')
        assert executor._pull_sub is None and not sub._pull_wanted
        publisher.publish(Int32(data=1))
        wait_for(lambda: received == [1], message=lambda: f'[1] through the pump, have {received}')
        node.destroy_timer(timer)
        wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='pulling again')
        publisher.publish(Int32(data=2))
        wait_for(lambda: received == [1, 2], message=lambda: f'[1, 2], have {received}')
        # a subscription made inside a callback: the spin goes back to the pumps at once
        node.create_guard_condition(
            lambda: node.create_subscription(Int32, '/pulled_second', lambda m: second.append(m.data), 10)).trigger()
        wait_for(lambda: executor._pull_sub is None, message='the second subscription seen')
        other = Node('pull_pub2', context=make_context()).create_publisher(Int32, '/pulled_second', 10)
        assert other.wait_for_subscribers(1, 5.0)
        other.publish(Int32(data=7))
        publisher.publish(Int32(data=3))
        wait_for(lambda: second == [7] and received == [1, 2, 3], message=lambda: f'{second}, {received}')
    finally:
        _stop(executor, spinner)


def test_shutdown_ends_a_pulling_spin_at_once(make_context, wait_for):
    _, sub, _, executor = _pair(make_context, '/pulled_shutdown', lambda m: None)
    spinner = _spinning(executor)
    wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
    start = time.monotonic()
    executor.shutdown()
    spinner.join(5)
    assert not spinner.is_alive()
    assert time.monotonic() - start < 0.5   # woken, not found by a timeout
    assert not sub._pull_wanted   # the pump receives again


def test_an_exception_in_a_pulled_callback_leaves_spin_and_the_rest_waits(make_context, wait_for):
    received = []

    def on_message(msg):
        if msg.data == 1:
            raise ValueError('bad sample')
        received.append(msg.data)
    publisher, sub, _, executor = _pair(make_context, '/pulled_raise', on_message, KEEP_ALL)
    errors = []
    spinner = _spinning(executor, errors=errors)
    wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
    for i in range(3):
        publisher.publish(Int32(data=i))
    spinner.join(5)
    assert [str(e) for e in errors] == ['bad sample']
    assert not sub._pull_wanted
    spinner = _spinning(executor)   # the next spin delivers what came after
    try:
        wait_for(lambda: received == [0, 2], message=lambda: f'[0, 2], have {received}')
    finally:
        _stop(executor, spinner)
    assert sub.lost == 0


def test_spin_until_future_complete_pulls_and_returns_on_the_future(make_context, wait_for):
    future = Future()
    seen = []

    def on_message(msg):
        seen.append(executor._pull_sub is sub)
        future.set_result(msg.data)
    publisher, sub, _, executor = _pair(make_context, '/pulled_future', on_message)
    done = []
    spinner = _spinning(executor, lambda: (executor.spin_until_future_complete(future), done.append(1)))
    try:
        wait_for(lambda: executor._pulling, message='the spin pulling')
        publisher.publish(Int32(data=5))
        spinner.join(5)
        assert done and future.result() == 5 and seen == [True]
    finally:
        _stop(executor, spinner)


@pytest.mark.parametrize('kind', ['message-info', 'async'])
def test_message_info_and_async_callbacks_are_pulled_too(make_context, wait_for, kind):
    received = []
    if kind == 'message-info':
        def callback(msg, info):
            received.append((msg.data, info['publication_sequence_number'] > 0))
    else:
        async def callback(msg):
            received.append((msg.data, True))
    publisher, sub, _, executor = _pair(make_context, f'/pulled_{kind.replace("-", "_")}', callback, KEEP_ALL)
    spinner = _spinning(executor)
    try:
        wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
        for i in range(50):
            publisher.publish(Int32(data=i))
        wait_for(lambda: len(received) == 50, message=lambda: f'50, have {len(received)}')
    finally:
        _stop(executor, spinner)
    assert received == [(i, True) for i in range(50)]


def test_destroying_the_pulled_subscription_goes_back_to_waiting(make_context, wait_for):
    _, sub, node, executor = _pair(make_context, '/pulled_destroyed', lambda m: None)
    ticks = []
    spinner = _spinning(executor)
    try:
        wait_for(lambda: executor._pull_sub is sub and executor._pulling, message='the spin pulling')
        node.destroy_subscription(sub)
        node.create_timer(0.01, lambda: ticks.append(1))
        wait_for(lambda: len(ticks) >= 2, message='the spin running a timer afterwards')
    finally:
        _stop(executor, spinner)


def test_a_pulled_callback_may_destroy_its_own_subscription(make_context, wait_for):
    received, ticks = [], []

    def on_message(msg):
        received.append(msg.data)
        node.destroy_subscription(sub)
        node.create_timer(0.01, lambda: ticks.append(1))
    publisher, sub, node, executor = _pair(make_context, '/pulled_self_destroyed', on_message, KEEP_ALL)
    errors = []
    spinner = _spinning(executor, errors=errors)
    try:
        wait_for(lambda: executor._pulling, message='the spin pulling')
        for i in range(20):
            publisher.publish(Int32(data=i))
        wait_for(lambda: len(ticks) >= 2, message='the timer made in the callback firing')
    finally:
        _stop(executor, spinner)
    assert errors == [] and received[0] == 0
    assert len(received) <= 20


def test_a_pulled_tf_subscription_beside_a_transform_listener_wakes_without_noise(make_context, wait_for, log_records):
    """The wake-up is put on the topic's key inside the session: the process's TF listener
    (a plain Zenoh subscriber on /tf) sees it and ignores it, logging nothing."""
    from zros.tf2_ros import Buffer, TransformListener
    from interfaces.tf2_msgs.msg import TFMessage
    ctx = make_context()
    node = Node('tf_pulled', context=ctx)
    buffer = Buffer()
    TransformListener(buffer, node, spin_thread=False)
    node.create_subscription(TFMessage, '/tf', lambda m: None, 10)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    spinner = _spinning(executor)
    tasked = []
    try:
        wait_for(lambda: executor._pulling, message='the spin pulling')
        for _ in range(3):
            executor.create_task(lambda: tasked.append(1))   # each one a wake-up on /tf
            wait_for(lambda: executor._pulling, message='pulling again')
        wait_for(lambda: len(tasked) == 3, message='the tasks')
    finally:
        _stop(executor, spinner)
    assert [r for r in log_records if 'dropping messages' in r[2]] == []
