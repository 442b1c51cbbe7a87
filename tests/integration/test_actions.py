"""Actions end to end: goals, feedback, results, cancellation, status, failures and the CLI."""
from __future__ import annotations

import threading
import time

import pytest

from zros.action import ActionClient, ActionServer, CancelResponse
from zros.action.server import GoalStatus
from zros.callback_groups import ReentrantCallbackGroup
from zros.errors import ServiceCallError
from zros.executors import MultiThreadedExecutor, SingleThreadedExecutor
from zros.node import Node


@pytest.fixture
def Fibonacci():
    from interfaces.action_tutorials_interfaces.action import Fibonacci
    return Fibonacci


@pytest.fixture
def fibonacci_server(spawn):
    child = spawn.node('demo_nodes', 'fibonacci_action_server', '--ros-args', '-p', 'step_period:=0.05')
    return child


class Spinner:
    """Spins an executor in a background thread until closed."""

    def __init__(self, executor) -> None:
        self.executor = executor
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        try:
            self.executor.spin()
        except Exception:  # noqa: BLE001 - ends when the context shuts down
            pass

    def close(self) -> None:
        self.executor.shutdown()
        self.thread.join(timeout=5)


@pytest.fixture
def client_node(context):
    node = Node('action_test_client', context=context)
    spinner = Spinner(MultiThreadedExecutor(context=context))
    spinner.executor.add_node(node)
    yield node
    spinner.close()


def _client(node, Fibonacci, name='fibonacci'):
    client = ActionClient(node, Fibonacci, name)
    assert client.wait_for_server(timeout_sec=10), 'action server never appeared'
    return client


def _send(client, goal, feedback=None, timeout=10.0):
    future = client.send_goal_async(goal, feedback_callback=feedback)
    assert future.wait(timeout), 'no answer to the goal'
    return future.result()


def test_success_with_ordered_feedback(client_node, fibonacci_server, Fibonacci):
    client = _client(client_node, Fibonacci)
    feedback = []
    handle = _send(client, Fibonacci.Goal(order=6), feedback.append)
    assert handle.accepted and len(bytes(handle.goal_id.uuid)) == 16
    result_future = handle.get_result_async()
    assert result_future.wait(10)
    response = result_future.result()
    assert response.status == GoalStatus.SUCCEEDED
    assert list(response.result.sequence) == [0, 1, 1, 2, 3, 5, 8]
    lengths = [len(f.feedback.partial_sequence) for f in feedback]
    assert lengths == sorted(lengths) and lengths[-1] == 7 and len(lengths) == 5
    assert all(f.goal_id == handle.goal_id for f in feedback)


def test_goal_rejected_by_goal_callback(client_node, fibonacci_server, Fibonacci):
    client = _client(client_node, Fibonacci)
    handle = _send(client, Fibonacci.Goal(order=-1))
    assert not handle.accepted
    assert client.send_goal(Fibonacci.Goal(order=-3)) is None


def test_cancel_accepted_leaves_other_goals_running(client_node, fibonacci_server, Fibonacci):
    client = _client(client_node, Fibonacci)
    doomed = _send(client, Fibonacci.Goal(order=40))
    survivor = _send(client, Fibonacci.Goal(order=8))
    cancel = doomed.cancel_goal_async()
    assert cancel.wait(5)
    assert len(cancel.result().goals_canceling) == 1
    doomed_result = doomed.get_result_async()
    survivor_result = survivor.get_result_async()
    assert doomed_result.wait(10) and survivor_result.wait(10)
    assert doomed_result.result().status == GoalStatus.CANCELED
    assert survivor_result.result().status == GoalStatus.SUCCEEDED
    assert list(survivor_result.result().result.sequence)[-1] == 21


def _in_process_server(make_context, Fibonacci, execute, **kwargs):
    ctx = make_context()
    node = Node('in_process_server', context=ctx)
    server = ActionServer(node, Fibonacci, 'local_fib', execute, callback_group=ReentrantCallbackGroup(), **kwargs)
    spinner = Spinner(MultiThreadedExecutor(num_threads=4, context=ctx))
    spinner.executor.add_node(node)
    return node, server, spinner


def test_cancel_rejected_by_default_and_abort(make_context, client_node, Fibonacci):
    release = threading.Event()

    def execute(goal_handle):
        release.wait(5)
        if goal_handle.request.order == 13:
            goal_handle.abort()
            return Fibonacci.Result(sequence=[13])
        goal_handle.succeed()
        return Fibonacci.Result(sequence=[1])
    _, _, spinner = _in_process_server(make_context, Fibonacci, execute)
    try:
        client = _client(client_node, Fibonacci, 'local_fib')
        handle = _send(client, Fibonacci.Goal(order=2))
        cancel = handle.cancel_goal_async()
        assert cancel.wait(5)
        assert cancel.result().return_code == 1 and not cancel.result().goals_canceling  # ERROR_REJECTED
        aborted = _send(client, Fibonacci.Goal(order=13))
        release.set()
        assert handle.get_result_async().wait(5)
        result = aborted.get_result_async()
        assert result.wait(5)
        assert result.result().status == GoalStatus.ABORTED and list(result.result().result.sequence) == [13]
    finally:
        spinner.close()


def test_three_concurrent_goals_each_get_their_own_feedback(make_context, client_node, Fibonacci):
    def execute(goal_handle):
        for step in range(5):
            goal_handle.publish_feedback(Fibonacci.Feedback(partial_sequence=[goal_handle.request.order, step]))
            time.sleep(0.05)
        goal_handle.succeed()
        return Fibonacci.Result(sequence=[goal_handle.request.order])
    _, _, spinner = _in_process_server(make_context, Fibonacci, execute)
    try:
        client = _client(client_node, Fibonacci, 'local_fib')
        other_client = _client(client_node, Fibonacci, 'local_fib')
        streams = {order: [] for order in (101, 102, 103)}
        other_feedback = []
        handles = [_send(client, Fibonacci.Goal(order=o), streams[o].append) for o in streams]
        other = _send(other_client, Fibonacci.Goal(order=7), other_feedback.append)
        started = time.monotonic()
        results = [h.get_result_async() for h in handles + [other]]
        assert all(r.wait(10) for r in results)
        assert time.monotonic() - started < 1.0, 'goals did not run concurrently'
        for order, stream in streams.items():
            assert [list(f.feedback.partial_sequence) for f in stream] == [[order, s] for s in range(5)]
        assert [list(f.feedback.partial_sequence)[0] for f in other_feedback] == [7] * 5
    finally:
        spinner.close()


def test_result_fetched_after_the_goal_finished(make_context, client_node, Fibonacci):
    def execute(goal_handle):
        goal_handle.succeed()
        return Fibonacci.Result(sequence=[4, 2])
    _, _, spinner = _in_process_server(make_context, Fibonacci, execute)
    try:
        client = _client(client_node, Fibonacci, 'local_fib')
        handle = _send(client, Fibonacci.Goal(order=1))
        time.sleep(0.5)
        result = handle.get_result_async()
        assert result.wait(5)
        assert result.result().status == GoalStatus.SUCCEEDED and list(result.result().result.sequence) == [4, 2]
    finally:
        spinner.close()


def test_server_killed_mid_goal_fails_the_result_future(spawn, client_node, Fibonacci):
    server = spawn.node('demo_nodes', 'fibonacci_action_server', '--ros-args', '-p', 'step_period:=1.0')
    client = _client(client_node, Fibonacci)
    handle = _send(client, Fibonacci.Goal(order=30))
    result = handle.get_result_async()
    server.wait_for_output('Executing goal', timeout=10)
    server.kill()
    assert result.wait(5), 'the result future hung after the server died'
    assert isinstance(result.exception(), ServiceCallError)
    assert 'did not deliver the result' in str(result.exception())


def test_custom_action_from_interface_path(tmp_path, monkeypatch, make_context, client_node):
    folder = tmp_path / 'custom_action_pkg' / 'action'
    folder.mkdir(parents=True)
    (folder / 'Countdown.action').write_text('int32 start\n---\nstring done\n---\nint32 remaining\n')
    monkeypatch.setenv('ZROS_INTERFACE_PATH', str(tmp_path))
    from interfaces.custom_action_pkg.action import Countdown

    def execute(goal_handle):
        for n in range(goal_handle.request.start, 0, -1):
            goal_handle.publish_feedback(Countdown.Feedback(remaining=n))
        goal_handle.succeed()
        return Countdown.Result(done='liftoff')
    ctx = make_context()
    node = Node('countdown_server', context=ctx)
    ActionServer(node, Countdown, 'countdown', execute)
    spinner = Spinner(SingleThreadedExecutor(context=ctx))
    spinner.executor.add_node(node)
    try:
        client = ActionClient(client_node, Countdown, 'countdown')
        assert client.wait_for_server(10)
        # the server's session is new: its feedback reaches the client once it knows the client's
        # feedback subscription (a loaded machine's new session may not yet when the goal comes)
        deadline = time.monotonic() + 10
        while node.count_subscribers('/countdown/_action/feedback') < 1 and time.monotonic() < deadline:
            time.sleep(0.05)
        feedback = []
        handle = _send(client, Countdown.Goal(start=3), feedback.append)
        result = handle.get_result_async()
        assert result.wait(5) and result.result().result.done == 'liftoff'
        time.sleep(0.2)
        assert [f.feedback.remaining for f in feedback] == [3, 2, 1]
    finally:
        spinner.close()


def test_action_cli(fibonacci_server, zros_cli, client_node, Fibonacci):
    _client(client_node, Fibonacci)
    both = 'action_tutorials_interfaces/action/Fibonacci, example_interfaces/action/Fibonacci'
    assert f'/fibonacci [{both}]' in zros_cli('action', 'list', '-t').stdout
    info = zros_cli('action', 'info', '/fibonacci').stdout
    assert 'Action: /fibonacci' in info and 'Action servers: 2' in info and '/fibonacci_action_server' in info
    assert 'Action clients: 1' in info
    assert zros_cli('action', 'type', '/fibonacci').stdout.split() == both.split(', ')
    sent = zros_cli('action', 'send_goal', '/fibonacci', 'action_tutorials_interfaces/action/Fibonacci',
                    '{order: 5}', '--feedback', timeout=30)
    assert sent.returncode == 0, sent
    out = sent.stdout
    # ros2 action send_goal's layout: only the first YAML line is indented
    assert out.startswith('Waiting for an action server to become available...\nSending goal:\n     order: 5\n\n')
    assert 'Goal accepted with ID: ' in out and 'Feedback:\n    partial_sequence:\n- 0\n' in out
    assert 'Result:\n    sequence:\n- 0\n- 1\n- 1\n- 2\n- 3\n- 5\n\nGoal finished' in out
    assert out.rstrip().endswith('Goal finished with status: SUCCEEDED')
    rejected = zros_cli('action', 'send_goal', '/fibonacci', 'action_tutorials_interfaces/action/Fibonacci', '{order: -1}')
    assert rejected.returncode == 1 and 'Goal was rejected.' in rejected.stdout
    node_info = zros_cli('node', 'info', '/fibonacci_action_server').stdout
    assert f'Action Servers:\n    /fibonacci: {both}' in node_info
    unknown = zros_cli('action', 'info', '/nope')
    assert unknown.returncode == 1 and 'Traceback' not in unknown.stderr


def test_send_goal_cli_cancels_on_ctrl_c(fibonacci_server, spawn, client_node, Fibonacci):
    import signal
    _client(client_node, Fibonacci)
    import sys
    child = spawn(sys.executable, '-m', 'zros', 'action', 'send_goal', '/fibonacci',
                  'action_tutorials_interfaces/action/Fibonacci', '{order: 200}', name='send_goal')
    child.wait_for_output('Goal accepted with ID', timeout=10)
    child.signal(signal.SIGINT)
    assert child.wait(timeout=10) == 130
    out = child.output()
    assert 'Canceling goal...' in out and 'Goal canceled.' in out


def test_goal_canceled_before_it_executes_ends_canceled(make_context, client_node, Fibonacci):
    """As in rclpy, the execute callback still runs (the goal stays CANCELING): it sees the
    cancel and ends the goal."""
    pending, saw_cancel = [], []

    def execute(goal_handle):
        saw_cancel.append(goal_handle.is_cancel_requested)
        goal_handle.canceled()
        return Fibonacci.Result()
    node, server, spinner = _in_process_server(
        make_context, Fibonacci, execute, handle_accepted_callback=pending.append,
        cancel_callback=lambda handle: CancelResponse.ACCEPT)
    try:
        client = _client(client_node, Fibonacci, 'local_fib')
        handle = _send(client, Fibonacci.Goal(order=3))
        cancel = handle.cancel_goal_async()
        assert cancel.wait(5) and len(cancel.result().goals_canceling) == 1
        pending[0].execute()
        result = handle.get_result_async()
        assert result.wait(5) and result.result().status == GoalStatus.CANCELED
        assert saw_cancel == [True]
        server.destroy()
        assert server not in node._entities
    finally:
        spinner.close()


def test_status_array_lists_retained_goals_and_drops_expired_ones(make_context, client_node, Fibonacci):
    """The status array is assembled from cached entries: it must still list every retained
    goal with its current status, and forget goals whose results expired."""
    from interfaces.action_msgs.msg import GoalStatusArray
    server_ctx = make_context()
    server_node = Node('status_server', context=server_ctx)
    ActionServer(server_node, Fibonacci, 'status_fib', lambda gh: (gh.succeed(), Fibonacci.Result())[1],
                 result_timeout=0.5)
    spinner = Spinner(SingleThreadedExecutor(context=server_ctx))
    spinner.executor.add_node(server_node)
    arrays = []
    client_node.create_subscription(GoalStatusArray, 'status_fib/_action/status', arrays.append, 10)
    try:
        client = _client(client_node, Fibonacci, 'status_fib')
        first = [client.send_goal(Fibonacci.Goal(order=i)) for i in range(3)]
        assert all(r.status == GoalStatus.SUCCEEDED for r in first)
        deadline = time.monotonic() + 5
        while not (arrays and [s.status for s in arrays[-1].status_list] == [GoalStatus.SUCCEEDED] * 3) \
                and time.monotonic() < deadline:
            time.sleep(0.02)
        assert [s.status for s in arrays[-1].status_list] == [GoalStatus.SUCCEEDED] * 3
        time.sleep(0.6)  # the three results expire
        handle = _send(client, Fibonacci.Goal(order=1))
        assert handle.get_result().status == GoalStatus.SUCCEEDED
        while not (arrays and len(arrays[-1].status_list) == 1 and arrays[-1].status_list[0].status == 4) \
                and time.monotonic() < deadline + 5:
            time.sleep(0.02)
        latest = arrays[-1].status_list
        assert len(latest) == 1 and latest[0].goal_info.goal_id == handle.goal_id
    finally:
        spinner.close()


def test_blocking_send_goal_is_one_exchange_and_falls_back_to_get_result(make_context, client_node, Fibonacci):
    """A blocking send_goal asks for the result in the send-goal query (a second reply when the
    goal ends); a server that answers only the acceptance is asked with get_result."""
    def execute(goal_handle):
        time.sleep(0.1)  # the result comes well after the acceptance
        goal_handle.succeed()
        return Fibonacci.Result(sequence=[goal_handle.request.order])
    _, server, spinner = _in_process_server(make_context, Fibonacci, execute)
    send_goal, get_result = server._services
    try:
        client = _client(client_node, Fibonacci, 'local_fib')
        results = [client.send_goal(Fibonacci.Goal(order=i)) for i in (3, 4)]
        assert [(r.status, list(r.result.sequence)) for r in results] == [(GoalStatus.SUCCEEDED, [3]),
                                                                            (GoalStatus.SUCCEEDED, [4])]
        get_result_calls = []
        get_result.callback = lambda request, response: (get_result_calls.append(request),
                                                         server._on_get_result(request, response))[1]
        assert client.send_goal(Fibonacci.Goal(order=5)).result.sequence.tolist() == [5]
        assert get_result_calls == []
        send_goal._follow_up = None   # a server without the second reply
        result = client.send_goal(Fibonacci.Goal(order=6))
        assert (result.status, list(result.result.sequence)) == (GoalStatus.SUCCEEDED, [6])
        assert len(get_result_calls) == 1
    finally:
        spinner.close()
