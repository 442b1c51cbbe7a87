"""rclpy's executor semantics that others' programs rely on (issue 12, items 3, 4 and 5):
`async def` callbacks run as tasks that await futures, spin_once returns on a completed
future, guard conditions, and an Executor subclass built on wait_for_ready_callbacks.

The programs below are written the way ROS 2 examples write them and run as processes.
"""
from __future__ import annotations

import sys
import threading
import time

import pytest

from zros.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.task import Future

from interfaces.std_msgs.msg import String

ASYNC_SERVICES = '''
import sys
import zros
from zros.callback_groups import MutuallyExclusiveCallbackGroup
from zros.executors import ExternalShutdownException
from zros.node import Node
from interfaces.example_interfaces.srv import AddTwoInts


class Chained(Node):
    """An async service that awaits another service, and an async timer that awaits it. As in
    rclpy, the timer keeps its callback group while it awaits, so the service it calls needs a
    group of its own."""

    def __init__(self):
        super().__init__('chained')
        self.cli = self.create_client(AddTwoInts, 'add_two_ints')
        self.srv = self.create_service(AddTwoInts, 'add_twice', self.add_twice,
                                       callback_group=MutuallyExclusiveCallbackGroup())
        self.own = self.create_client(AddTwoInts, 'add_twice')
        self.timer = self.create_timer(0.2, self.tick)
        self.n = 0

    async def add_twice(self, request, response):
        first = await self.cli.call_async(AddTwoInts.Request(a=request.a, b=request.b))
        second = await self.cli.call_async(AddTwoInts.Request(a=first.sum, b=request.b))
        response.sum = second.sum
        return response

    async def tick(self):
        self.n += 1
        if self.n > 3:
            return
        result = await self.own.call_async(AddTwoInts.Request(a=self.n, b=10))
        print(f'add_twice({self.n}, 10) = {result.sum}', flush=True)


def main():
    try:
        with zros.init(args=sys.argv):
            node = Chained()
            node.cli.wait_for_service(10)
            print('ready', flush=True)
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


main()
'''


def test_async_service_and_timer_callbacks_await_calls(spawn):
    spawn.node('demo_nodes', 'add_two_ints_server')
    child = spawn(sys.executable, '-c', ASYNC_SERVICES, name='chained')
    for n in (1, 2, 3):
        child.wait_for_output(f'add_twice({n}, 10) = {n + 20}', timeout=20)
    assert 'Traceback' not in child.output() and 'coroutine' not in child.output()


ASYNC_ACTIONS = '''
import sys
import zros
from zros.action import ActionClient, ActionServer
from zros.executors import ExternalShutdownException, SingleThreadedExecutor
from zros.node import Node
from interfaces.action_tutorials_interfaces.action import Fibonacci
from interfaces.example_interfaces.srv import AddTwoInts


class Server(Node):
    """Fibonacci whose async execute callback awaits a service call for each term."""

    def __init__(self):
        super().__init__('async_fibonacci_server')
        self.adder = self.create_client(AddTwoInts, 'add_two_ints')
        ActionServer(self, Fibonacci, 'fibonacci_async', self.execute)

    async def execute(self, goal_handle):
        sequence = [0, 1]
        for _ in range(1, goal_handle.request.order):
            total = await self.adder.call_async(AddTwoInts.Request(a=sequence[-1], b=sequence[-2]))
            sequence.append(total.sum)
            goal_handle.publish_feedback(Fibonacci.Feedback(partial_sequence=sequence))
        goal_handle.succeed()
        return Fibonacci.Result(sequence=sequence)


class Client(Node):
    """An async timer callback that awaits the goal's acceptance and then its result."""

    def __init__(self):
        super().__init__('async_fibonacci_client')
        self.client = ActionClient(self, Fibonacci, 'fibonacci_async')
        self.timer = self.create_timer(0.1, self.run)

    async def run(self):
        self.timer.cancel()
        self.client.wait_for_server(10)
        goal_handle = await self.client.send_goal_async(Fibonacci.Goal(order=8))
        print('accepted', goal_handle.accepted, flush=True)
        response = await goal_handle.get_result_async()
        print('result', list(response.result.sequence), flush=True)


def main():
    try:
        with zros.init(args=sys.argv):
            executor = SingleThreadedExecutor()
            server = Server()
            server.adder.wait_for_service(10)
            executor.add_node(server)
            executor.add_node(Client())
            executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


main()
'''


def test_async_action_execute_and_awaited_goal_handles(spawn):
    spawn.node('demo_nodes', 'add_two_ints_server')
    child = spawn(sys.executable, '-c', ASYNC_ACTIONS, name='fib')
    child.wait_for_output('result [0, 1, 1, 2, 3, 5, 8, 13, 21]', timeout=25)
    assert 'accepted True' in child.output() and 'Traceback' not in child.output()


SPIN_ONCE_CLIENT = '''
import sys, time
import zros
from zros.node import Node
from interfaces.example_interfaces.srv import AddTwoInts


class MinimalClientAsync(Node):
    def __init__(self):
        super().__init__('minimal_client_async')
        self.cli = self.create_client(AddTwoInts, 'add_two_ints')
        while not self.cli.wait_for_service(timeout_sec=1.0):
            self.get_logger().info('service not available, waiting again...')

    def send_request(self, a, b):
        self.future = self.cli.call_async(AddTwoInts.Request(a=a, b=b))


def main():
    zros.init(args=sys.argv)
    client = MinimalClientAsync()
    for a, pause in ((1, 0.0), (2, 1.0)):       # the second answer is in before spin_once runs
        client.send_request(a, 40)
        time.sleep(pause)
        while zros.ok():
            zros.spin_once(client)
            if client.future.done():
                print('sum', client.future.result().sum, flush=True)
                break
    client.destroy_node()
    zros.shutdown()


main()
'''


def test_spin_once_without_timeout_returns_when_the_response_arrives(spawn):
    spawn.node('demo_nodes', 'add_two_ints_server')
    child = spawn(sys.executable, '-c', SPIN_ONCE_CLIENT, name='spin_once_client')
    assert child.wait(30) == 0, child.output()
    assert 'sum 41' in child.output() and 'sum 42' in child.output()


EXECUTOR_SUBCLASS = '''
import os, sys, threading
from concurrent.futures import ThreadPoolExecutor
import zros
from zros.executors import Executor, ExternalShutdownException
from zros.node import Node
from interfaces.std_msgs.msg import String


class PriorityExecutor(Executor):
    """Runs the callbacks of high-priority nodes on their own pool (the rclpy example)."""

    def __init__(self):
        super().__init__()
        self.high_priority_nodes = set()
        self.hp_executor = ThreadPoolExecutor(max_workers=os.cpu_count() or 4)
        self.lp_executor = ThreadPoolExecutor(max_workers=1)

    def add_high_priority_node(self, node):
        self.high_priority_nodes.add(node)
        self.add_node(node)

    def shutdown(self, timeout_sec=None):
        self.hp_executor.shutdown()
        self.lp_executor.shutdown()
        return super().shutdown(timeout_sec=timeout_sec)

    def spin_once(self, timeout_sec=None):
        try:
            handler, group, node = self.wait_for_ready_callbacks(timeout_sec=timeout_sec)
        except StopIteration:
            pass
        else:
            if node in self.high_priority_nodes:
                self.hp_executor.submit(handler)
            else:
                self.lp_executor.submit(handler)


class Talker(Node):
    def __init__(self, name):
        super().__init__(name)
        self.pub = self.create_publisher(String, 'prio_chatter', 10)
        self.create_timer(0.05, self.tick)
        self.i = 0

    def tick(self):
        self.i += 1
        self.pub.publish(String(data=f'{self.get_name()} {self.i}'))


class Listener(Node):
    def __init__(self):
        super().__init__('prio_listener')
        self.threads = set()
        self.heard = 0
        self.create_subscription(String, 'prio_chatter', self.on_message, 10)

    def on_message(self, msg):
        self.threads.add(threading.current_thread().name)
        self.heard += 1
        if self.heard == 20:
            print('heard 20 on', sorted(n.split('_')[0] for n in self.threads), flush=True)


def main():
    try:
        with zros.init(args=sys.argv):
            executor = PriorityExecutor()
            executor.add_high_priority_node(Listener())
            executor.add_node(Talker('prio_talker'))
            print('spinning', flush=True)
            executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        print('stopped cleanly', flush=True)


main()
'''


def test_an_executor_subclass_built_on_wait_for_ready_callbacks(spawn):
    import signal
    child = spawn(sys.executable, '-c', EXECUTOR_SUBCLASS, name='priority')
    child.wait_for_output('heard 20 on', timeout=20)
    assert "heard 20 on ['ThreadPoolExecutor-0']" in child.output(), child.output()
    child.signal(signal.SIGINT)
    assert child.wait(10) == 0 and 'stopped cleanly' in child.output(), child.output()


# -- semantics in one process --------------------------------------------------------------------
def _spin_until(executor, predicate, timeout=5.0):
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, 'timed out'
        executor.spin_once(timeout_sec=0.05)


@pytest.mark.parametrize('group_kind', ['exclusive', 'reentrant'])
def test_a_suspended_async_callback_keeps_its_callback_group(context, group_kind):
    """As rclpy: while an async callback awaits, other callbacks of a mutually exclusive group
    wait; those of a reentrant group run."""
    node = Node('holder', context=context)
    group = MutuallyExclusiveCallbackGroup() if group_kind == 'exclusive' else ReentrantCallbackGroup()
    gate = Future()
    events = []

    async def waiting():
        events.append('waiting')
        await gate
        events.append('resumed')
    timer = node.create_timer(0.01, lambda: events.append('tick'), callback_group=group)
    node.create_guard_condition(waiting, callback_group=group).trigger()
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    _spin_until(executor, lambda: 'waiting' in events)
    events.clear()
    deadline = time.monotonic() + 0.3
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    assert ('tick' in events) == (group_kind == 'reentrant'), events
    threading.Timer(0.05, gate.set_result, args=(None,)).start()   # completed on another thread
    _spin_until(executor, lambda: 'resumed' in events)
    _spin_until(executor, lambda: events.count('tick') >= 2)
    timer.cancel()


def test_guard_condition_triggers_collapse_and_run_on_the_executor(context):
    node = Node('guarded', context=context)
    calls = []
    guard = node.create_guard_condition(lambda: calls.append(threading.current_thread()))
    for _ in range(5):
        guard.trigger()                 # before anyone spins: remembered, once
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    executor.spin_once(timeout_sec=1.0)
    assert calls == [threading.current_thread()]
    threading.Thread(target=guard.trigger).start()
    executor.spin_once(timeout_sec=2.0)
    assert len(calls) == 2 and calls[1] is threading.current_thread()
    assert guard in node.guards and node.destroy_guard_condition(guard) and guard not in node.guards


def test_create_task_awaits_and_returns(context):
    executor = SingleThreadedExecutor(context=context)
    gate = Future()

    async def job(x):
        y = await gate
        return x + y
    task = executor.create_task(job, 2)
    executor.spin_once(timeout_sec=0.5)
    assert not task.done()
    gate.set_result(40)
    executor.spin_until_future_complete(task, timeout_sec=2)
    assert task.result() == 42


def test_an_exception_in_an_async_callback_leaves_spin(context):
    node = Node('raiser', context=context)

    async def broken():
        raise ValueError('from a coroutine')
    node.create_timer(0.01, broken)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    with pytest.raises(ValueError, match='from a coroutine'):
        executor.spin_once(timeout_sec=2)


def test_subscription_async_callbacks(context, wait_for):
    node = Node('async_sub', context=context)
    got = []

    async def on_message(msg):
        got.append(msg.data)
    node.create_subscription(String, 'async_topic', on_message, 10)
    publisher = node.create_publisher(String, 'async_topic', 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    for i in range(3):
        publisher.publish(String(data=str(i)))
    _spin_until(executor, lambda: len(got) == 3)
    assert got == ['0', '1', '2']
