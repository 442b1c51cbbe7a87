"""Executors, timers, futures, callback groups, the context life cycle and signals."""
from __future__ import annotations

import signal
import threading
import time

import pytest

import zros
from zros.errors import NotInitializedError
from zros.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from zros.executors import ExternalShutdownException, MultiThreadedExecutor, SingleThreadedExecutor
from zros.node import Node
from zros.task import Future

from interfaces.std_msgs.msg import String


def _spin_for(executor, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while (remaining := deadline - time.monotonic()) > 0:
        executor.spin_once(timeout_sec=remaining)


# -- timers ------------------------------------------------------------------------------------
def test_timer_period(context):
    node = Node('timed', context=context)
    calls = []
    created = time.monotonic()
    timer = node.create_timer(0.05, lambda: calls.append(time.monotonic()))
    assert timer.timer_period_ns == 50_000_000
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    _spin_for(executor, 0.52)
    assert 8 <= len(calls) <= 11, len(calls)
    assert calls[0] - created >= 0.045  # the first call comes one period after creation
    gaps = [b - a for a, b in zip(calls, calls[1:])]
    assert sum(gaps) / len(gaps) == pytest.approx(0.05, abs=0.01)


def test_timer_cancel_and_reset(context):
    node = Node('timed', context=context)
    calls = []
    timer = node.create_timer(0.03, lambda: calls.append(1))
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    _spin_for(executor, 0.2)
    assert calls
    timer.cancel()
    assert timer.is_canceled()
    assert timer.time_until_next_call() is None
    count = len(calls)
    _spin_for(executor, 0.2)
    assert len(calls) == count
    timer.reset()
    assert not timer.is_canceled()
    assert 0 < timer.time_until_next_call() <= 30_000_000
    _spin_for(executor, 0.2)
    assert len(calls) > count
    # destroyed timers stop for good
    assert node.destroy_timer(timer)
    count = len(calls)
    _spin_for(executor, 0.15)
    assert len(calls) == count


def test_timer_without_autostart(context):
    node = Node('timed', context=context)
    calls = []
    timer = node.create_timer(0.02, lambda: calls.append(1), autostart=False)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    _spin_for(executor, 0.1)
    assert calls == [] and timer.is_canceled()
    timer.reset()
    _spin_for(executor, 0.1)
    assert calls


def test_invalid_timer_period(context):
    node = Node('timed', context=context)
    with pytest.raises(ValueError):
        node.create_timer(0, lambda: None)


# -- spin_once and futures ----------------------------------------------------------------
def test_spin_once_times_out_when_idle(context):
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(Node('idle', context=context))
    for timeout in (0.0, 0.2):
        start = time.monotonic()
        executor.spin_once(timeout_sec=timeout)
        assert timeout - 0.01 <= time.monotonic() - start < timeout + 0.3


def test_spin_once_runs_one_callback(make_context):
    pub_ctx, ctx = make_context(), make_context()
    node = Node('one', context=ctx)
    received = []
    node.create_subscription(String, '/one', received.append, 10)
    publisher = Node('src', context=pub_ctx).create_publisher(String, '/one', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    publisher.publish(String(data='a'))
    publisher.publish(String(data='b'))
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    deadline = time.monotonic() + 5
    while not received and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert [m.data for m in received] == ['a']  # one spin_once, one callback
    executor.spin_once(timeout_sec=1.0)
    assert [m.data for m in received] == ['a', 'b']


def test_spin_once_with_zero_timeout_polls_ready_work(make_context):
    """`spin_once(timeout_sec=0)` in a loop (a game loop's poll) runs what is ready."""
    pub_ctx, ctx = make_context(), make_context()
    node = Node('poller', context=ctx)
    received = []
    node.create_subscription(String, '/poll', received.append, 10)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(node)
    publisher = Node('src', context=pub_ctx).create_publisher(String, '/poll', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    for i in range(3):
        publisher.publish(String(data=str(i)))
    deadline = time.monotonic() + 5
    while len(received) < 3 and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0)
        time.sleep(0.005)
    assert [m.data for m in received] == ['0', '1', '2']


def test_a_wake_up_alone_does_not_end_spin_once(context):
    """Adding a node (or any other wake-up) does not make spin_once return with nothing done:
    it keeps waiting for work until the timeout, as rclpy does."""
    node = Node('late_timer', context=context)
    ticks = []
    node.create_timer(0.1, lambda: ticks.append(time.monotonic()))
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)  # wakes the executor
    start = time.monotonic()
    executor.spin_once(timeout_sec=2.0)
    assert len(ticks) == 1
    assert 0.08 <= ticks[0] - start < 0.5


def test_spin_until_future_complete_from_another_thread(context):
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(Node('waiter', context=context))
    future = Future()
    completer = threading.Timer(0.2, future.set_result, args=('done',))
    start = time.monotonic()
    completer.start()
    try:
        executor.spin_until_future_complete(future, timeout_sec=5.0)
    finally:
        completer.cancel()
    elapsed = time.monotonic() - start
    assert future.done() and future.result() == 'done'
    assert 0.15 <= elapsed < 0.45, elapsed  # woken by the completion, not a poll or the timeout


def test_spin_until_future_complete_timeout(context):
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(Node('waiter', context=context))
    future = Future()
    start = time.monotonic()
    executor.spin_until_future_complete(future, timeout_sec=0.3)
    assert 0.28 <= time.monotonic() - start < 0.8
    assert not future.done()


def test_future_done_callbacks_run_on_the_executor(context):
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(Node('waiter', context=context))
    future = Future()
    ran_on = []
    executor._adopt(future)
    future.add_done_callback(lambda f: ran_on.append((threading.current_thread(), f.result())))
    thread = threading.Thread(target=future.set_result, args=(7,))
    thread.start()
    thread.join()
    assert ran_on == []  # not in the completing thread
    executor.spin_until_future_complete(future, timeout_sec=1.0)
    executor.spin_once(timeout_sec=0.5)
    assert ran_on == [(threading.main_thread(), 7)]


def test_future_exception_and_cancel():
    future = Future()
    future.set_exception(KeyError('k'))
    assert future.done() and isinstance(future.exception(), KeyError)
    with pytest.raises(KeyError):
        future.result()
    cancelled = Future()
    cancelled.cancel()
    assert cancelled.cancelled() and cancelled.done()
    cancelled.set_result(1)  # too late: ignored
    assert cancelled.result() is None


def test_create_task_runs_on_the_executor(context):
    executor = SingleThreadedExecutor(context=context)
    future = executor.create_task(lambda a, b: a + b, 2, 3)
    executor.spin_until_future_complete(future, timeout_sec=2.0)
    assert future.result() == 5


# -- multi-threaded executor and callback groups -------------------------------------------
def _concurrency(context, group_factory, shared: bool) -> int:
    """Highest number of callbacks seen running at once, for two slow timers."""
    node = Node('busy', context=context)
    lock = threading.Lock()
    running = [0]
    peak = [0]
    calls = [0]

    def slow() -> None:
        with lock:
            running[0] += 1
            calls[0] += 1
            peak[0] = max(peak[0], running[0])
        time.sleep(0.15)
        with lock:
            running[0] -= 1
    group = group_factory()
    for _ in range(2):
        node.create_timer(0.02, slow, callback_group=group if shared else group_factory())
    executor = MultiThreadedExecutor(num_threads=4, context=context)
    executor.add_node(node)
    try:
        _spin_for(executor, 0.6)
    finally:
        executor.shutdown()
    assert calls[0] >= 3
    return peak[0]


def test_reentrant_group_runs_callbacks_in_parallel(context):
    assert _concurrency(context, ReentrantCallbackGroup, shared=True) >= 2


def test_mutually_exclusive_group_runs_callbacks_one_at_a_time(context):
    assert _concurrency(context, MutuallyExclusiveCallbackGroup, shared=True) == 1


def test_separate_exclusive_groups_run_in_parallel(context):
    assert _concurrency(context, MutuallyExclusiveCallbackGroup, shared=False) == 2


def test_slow_timer_in_exclusive_group_skips_missed_periods(context):
    """A timer whose callback outlasts its period is not queued up again and again while its
    group is busy (missed periods are skipped, as in rcl), and shutdown does not wait for a
    backlog of stale calls."""
    node = Node('slow', context=context)
    calls = []
    node.create_timer(0.01, lambda: (calls.append(1), time.sleep(0.1)),
                      callback_group=MutuallyExclusiveCallbackGroup())
    executor = MultiThreadedExecutor(num_threads=2, context=context)
    executor.add_node(node)
    _spin_for(executor, 0.5)
    start = time.monotonic()
    executor.shutdown()
    assert time.monotonic() - start < 0.3
    assert 3 <= len(calls) <= 6, len(calls)


def test_multithreaded_executor_delivers_messages(make_context):
    pub_ctx, ctx = make_context(), make_context()
    node = Node('mt', context=ctx)
    received = []
    node.create_subscription(String, '/mt', received.append, 100)
    publisher = Node('src', context=pub_ctx).create_publisher(String, '/mt', 100)
    assert publisher.wait_for_subscribers(1, 5.0)
    executor = MultiThreadedExecutor(num_threads=2, context=ctx)
    executor.add_node(node)
    try:
        for i in range(50):
            publisher.publish(String(data=str(i)))
        deadline = time.monotonic() + 5
        while len(received) < 50 and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)
    finally:
        executor.shutdown()
    # the node's default group is mutually exclusive, so order is kept
    assert [m.data for m in received] == [str(i) for i in range(50)]


# -- errors and shutdown --------------------------------------------------------------------
@pytest.mark.parametrize('executor_class', [SingleThreadedExecutor, MultiThreadedExecutor])
def test_exception_in_callback_propagates_out_of_spin(context, executor_class):
    node = Node('faulty', context=context)

    def boom() -> None:
        raise ValueError('boom from a timer')
    node.create_timer(0.02, boom)
    executor = executor_class(context=context)
    executor.add_node(node)
    done = threading.Event()
    watchdog = threading.Timer(5.0, lambda: done.is_set() or executor.shutdown())
    watchdog.start()
    try:
        with pytest.raises(ValueError, match='boom from a timer'):
            executor.spin()
    finally:
        done.set()
        watchdog.cancel()
        executor.shutdown()


def test_spin_ends_with_external_shutdown(make_context):
    ctx = make_context()
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(Node('doomed', context=ctx))
    threading.Timer(0.2, ctx.shutdown).start()
    start = time.monotonic()
    with pytest.raises(ExternalShutdownException):
        executor.spin()
    assert time.monotonic() - start < 1.5
    assert not ctx.ok()


def test_executor_shutdown_stops_spin(context):
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(Node('stopper', context=context))
    threading.Timer(0.2, executor.shutdown).start()
    start = time.monotonic()
    executor.spin()
    assert time.monotonic() - start < 1.5
    assert executor.get_nodes() == []


def test_multithreaded_shutdown_while_work_keeps_arriving(context):
    """shutdown() from another thread while spin is handing work to the pool: spin ends
    quietly (it once raised "cannot schedule new futures after shutdown" about one time in
    three)."""
    for _ in range(25):
        executor = MultiThreadedExecutor(context=context)
        errors: list[BaseException] = []
        stop = threading.Event()

        def feed() -> None:
            while not stop.is_set():
                executor.create_task(lambda: None)
                time.sleep(0)

        def spin() -> None:
            try:
                executor.spin()
            except BaseException as exc:  # noqa: BLE001 - the test reports what spin raised
                errors.append(exc)
        feeder = threading.Thread(target=feed)
        spinner = threading.Thread(target=spin)
        feeder.start()
        spinner.start()
        time.sleep(0.005)
        executor.shutdown()
        spinner.join(5)
        stop.set()
        feeder.join(5)
        assert not spinner.is_alive()
        assert errors == []


def test_spinning_twice_is_an_error(context):
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(Node('twice', context=context))
    spinner = threading.Thread(target=executor.spin)
    spinner.start()
    try:
        time.sleep(0.1)
        with pytest.raises(RuntimeError, match='already spinning'):
            executor.spin_once(timeout_sec=0.1)
    finally:
        executor.shutdown()
        spinner.join(5)
    assert not spinner.is_alive()


# -- the default context: zros.init / spin_* / shutdown ------------------------------------
def test_init_as_context_manager(domain):
    with zros.init(args=[], signal_handler_options=False) as ctx:
        assert zros.ok() and ctx is zros.get_default_context()
        assert ctx.domain_id == domain
        node = zros.create_node('managed')
        assert node.get_fully_qualified_name() == '/managed'
        with pytest.raises(RuntimeError):
            zros.init(args=[])  # once per context
    assert not zros.ok()
    with pytest.raises(NotInitializedError):
        Node('too_late')
    # and it can be initialized again afterwards
    with zros.init(args=[], signal_handler_options=False):
        assert zros.ok()
    assert not zros.ok()


def test_module_level_spin_functions(domain):
    with zros.init(args=[], signal_handler_options=False):
        node = zros.create_node('module_level')
        ticks = []
        node.create_timer(0.02, lambda: ticks.append(1))
        zros.spin_once(node, timeout_sec=1.0)
        assert ticks == [1]
        future = Future()
        threading.Timer(0.1, future.set_result, args=(42,)).start()
        zros.spin_until_future_complete(node, future, timeout_sec=3.0)
        assert future.result() == 42
        assert node.executor is None  # spin_* helpers detach the node again


def test_init_with_explicit_domain_and_ros_args(domain):
    other = (domain + 1) if domain < 232 else domain - 1
    from zros.context import Context
    ctx = Context().init(['prog', '--ros-args', '-r', '__ns:=/space'], domain_id=other,
                         install_signal_handlers=False)
    try:
        assert ctx.domain_id == other
        assert Node('n', context=ctx).get_fully_qualified_name() == '/space/n'
    finally:
        ctx.shutdown()


# -- signals to node processes -------------------------------------------------------------
@pytest.mark.parametrize('signum', [signal.SIGTERM, signal.SIGINT], ids=['SIGTERM', 'SIGINT'])
@pytest.mark.parametrize('executable', ['talker', 'listener'])
def test_signal_stops_a_spinning_node_cleanly(spawn, wait_for, signum, executable):
    child = spawn.node('demo_nodes', executable)
    # Wait until the node is spinning: its /chatter endpoint, made just before spin(), is in the
    # graph (the node itself is there earlier, and a Ctrl-C while it is built exits with 130).
    from zros.cli.common import cli_context, graph_entities
    with cli_context() as ctx:
        wait_for(lambda: any(e.node_fqn == f'/{executable}' and e.name == '/chatter' for e in graph_entities(ctx)),
                 timeout=10, message=lambda: f'/{executable}\'s /chatter in the graph:\n{child.output()}')
    child.signal(signum)
    start = time.monotonic()
    code = child.wait(5)
    assert code == 0, child.output()
    assert time.monotonic() - start < 5
    assert 'Traceback' not in child.output()


def test_sigterm_to_a_plain_script_ends_its_spin(spawn):
    """A script that only calls zros.spin() (no handler of its own) exits on SIGTERM."""
    script = spawn.script('''
import zros
from zros.executors import ExternalShutdownException
zros.init()
node = zros.create_node('plain')
print('spinning', flush=True)
try:
    zros.spin(node)
except ExternalShutdownException:
    print('external shutdown', flush=True)
''', name='plain')
    script.wait_for_output('spinning', timeout=10)
    time.sleep(0.1)
    script.signal(signal.SIGTERM)
    assert script.wait(5) == 0, script.output()
    assert 'external shutdown' in script.output()


# -- tasks made by create_task ----------------------------------------------------------------
def test_the_newest_task_runs_first(context):
    """rclpy's order: tasks not yet run are taken newest first, so a task made to await an
    earlier one starts before it, and resumes only once that one has finished."""
    executor = SingleThreadedExecutor(context=context)
    order = []

    async def first():
        order.append('first')
        return 1

    first_task = executor.create_task(first)

    async def second():
        order.append('second')
        return await first_task + 1

    second_task = executor.create_task(second)
    executor.spin_once(timeout_sec=0)
    executor.spin_once(timeout_sec=0)
    assert order == ['second', 'first'] and first_task.done() and not second_task.done()
    executor.spin_once(timeout_sec=1)
    assert second_task.result() == 2


def test_the_ready_callbacks_generator_stops_on_shutdown(context):
    """rclpy's `_wait_for_ready_callbacks` generator, which custom executors iterate."""
    from zros.executors import ShutdownException
    executor = SingleThreadedExecutor(context=context)
    ready = executor._wait_for_ready_callbacks()
    executor.shutdown()
    with pytest.raises(ShutdownException):
        next(ready)


def test_a_one_thread_multi_threaded_executor_warns(context):
    with pytest.warns(UserWarning, match='SingleThreadedExecutor'):
        executor = MultiThreadedExecutor(num_threads=1, context=context)
    executor.shutdown()
