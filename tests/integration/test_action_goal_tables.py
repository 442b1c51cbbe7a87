"""What an action client and server keep per goal stays bounded when a client replaces its goal
over and over without asking for the results, as bt_navigator does with FollowPath every
replanning period (issue 36's soak: the navigator's memory grew with every goal)."""
from __future__ import annotations

import gc
import threading
import time

from zros.action import ActionClient, ActionServer, CancelResponse
from zros.callback_groups import ReentrantCallbackGroup
from zros.executors import MultiThreadedExecutor
from zros.navigation.servers import GoalSlot
from zros.node import Node

GOALS = 40


def _spin(ctx, node):
    executor = MultiThreadedExecutor(num_threads=4, context=ctx)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    return executor


def test_replaced_goals_whose_results_nobody_asks_for_are_forgotten(make_context, wait_for):
    from interfaces.action_tutorials_interfaces.action import Fibonacci
    slot = GoalSlot()
    closing = threading.Event()

    def execute(handle):   # runs until a newer goal takes over, like controller_server's loop
        slot.take(handle)
        while slot.is_current(handle) and not handle.is_cancel_requested and not closing.is_set():
            handle.publish_feedback(Fibonacci.Feedback(partial_sequence=[1]))
            time.sleep(0.01)
        if handle.is_cancel_requested:
            handle.canceled()
        else:
            handle.abort()
        return Fibonacci.Result()

    server_ctx, client_ctx = make_context(), make_context()
    server_node, client_node = Node('replaced_server', context=server_ctx), Node('replacing', context=client_ctx)
    server = ActionServer(server_node, Fibonacci, 'replaced', execute, callback_group=ReentrantCallbackGroup(),
                          cancel_callback=lambda handle: CancelResponse.ACCEPT, result_timeout=3.0)
    executors = [_spin(server_ctx, server_node), _spin(client_ctx, client_node)]
    try:
        client = ActionClient(client_node, Fibonacci, 'replaced')
        assert client.wait_for_server(timeout_sec=10)
        feedback = []
        for _ in range(GOALS):   # the handle is dropped at once: nobody asks for the result
            future = client.send_goal_async(Fibonacci.Goal(order=1), feedback_callback=feedback.append)
            assert future.wait(5)
            del future
        sent = client.send_goal_async(Fibonacci.Goal(order=1))
        assert sent.wait(5)
        last = sent.result()
        assert wait_for(lambda: len(feedback) > 0, 5)
        # An ended goal's entry on the server is kept until result_timeout, without its request.
        ended = lambda: [g for g in list(server._goal_handles.values()) if not g.is_active]  # noqa: E731
        assert wait_for(lambda: len(ended()) >= GOALS, 5), len(ended())
        assert not any(hasattr(goal, 'request') or hasattr(goal, '_request') for goal in ended())
        gc.collect()
        assert len(client._handles) <= 1, 'the client keeps the handles of goals nobody holds'
        # The server reports each replaced goal ABORTED: their feedback callbacks go a little later.
        time.sleep(2.5)
        assert last.cancel_goal().goals_canceling
        assert last.get_result().status == 5   # CANCELED
        assert wait_for(lambda: not client._feedback_callbacks, 5), len(client._feedback_callbacks)
        assert len(client._settled) <= 2
        # The server forgets finished goals after result_timeout (3 s here, 900 s by default).
        assert wait_for(lambda: not server._goal_handles and not server._finished, 8), len(server._goal_handles)
        assert not server._status_heads and not server._status_tails and not server._changed
    finally:
        closing.set()
        for executor in executors:
            executor.shutdown(timeout_sec=5)


def test_a_clients_feedback_publisher_goes_with_its_last_retained_goal(make_context, wait_for):
    """The server publishes each client's feedback on a topic of its own; clients come and go (a
    mission script, each `zros action send_goal`), so the publisher goes once the client has no
    goal left on the server, and the server's Zenoh declarations do not grow with clients."""
    from interfaces.action_tutorials_interfaces.action import Fibonacci

    def execute(handle):
        handle.publish_feedback(Fibonacci.Feedback(partial_sequence=[1]))
        handle.succeed()
        return Fibonacci.Result(sequence=[1])

    server_ctx = make_context()
    server_node = Node('feedback_server', context=server_ctx)
    server = ActionServer(server_node, Fibonacci, 'short_lived_clients', execute, result_timeout=1.0)
    executors = [_spin(server_ctx, server_node)]
    tokens_before = len(server_node._tokens)
    try:
        for round_ in range(3):                 # three clients, one after another, two goals each
            client_ctx = make_context()
            client_node = Node(f'short_lived_{round_}', context=client_ctx)
            executors.append(_spin(client_ctx, client_node))
            client = ActionClient(client_node, Fibonacci, 'short_lived_clients')
            assert client.wait_for_server(timeout_sec=10)
            for _ in range(2):
                feedback = []
                assert client.send_goal(Fibonacci.Goal(order=1), feedback_callback=feedback.append).status == 4
            assert len(server._feedback_pubs) >= 1
            executors.pop().shutdown(timeout_sec=5)
            client_node.destroy_node()
        # Results are kept for result_timeout (1 s): then the goals, their clients' counts and
        # publishers go, and the server node has the declarations it started with.
        assert wait_for(lambda: not server._goal_handles, 8), len(server._goal_handles)
        assert not server._feedback_pubs and not server._client_goals
        assert len(server_node._tokens) == tokens_before
    finally:
        for executor in executors:
            executor.shutdown(timeout_sec=5)


_NAV2_SERVERS = r'''
import json, sys
import zros
from zros.action import ActionServer
from nodes.nav2_bt_navigator.bt_navigator import BtNavigator
from nodes.nav2_controller.controller_server import ControllerServer
from nodes.nav2_planner.planner_server import PlannerServer
with zros.init(args=sys.argv, signal_handler_options=False):
    nodes = [PlannerServer(), ControllerServer(), BtNavigator()]
    print(json.dumps({e.action_name: e._result_timeout for n in nodes for e in n._entities
                      if isinstance(e, ActionServer)}))
'''


def test_nav2_servers_keep_results_for_action_server_result_timeout(domain):
    """Nav2's `action_server_result_timeout` (Jazzy's defaults): 10 s in the servers the navigator
    sends a goal every replanning period, 900 s in the navigator a mission calls. With rcl's
    900 s everywhere, the planner kept 15 minutes of computed paths (the soak's growth)."""
    import json
    import subprocess
    import sys
    from conftest import REPO

    def timeouts(*args):
        out = subprocess.run([sys.executable, '-c', _NAV2_SERVERS, *args], capture_output=True, text=True,
                             timeout=60, cwd=REPO)
        assert out.returncode == 0, out.stderr
        return json.loads(out.stdout.strip().splitlines()[-1])
    default = timeouts()
    assert default['/compute_path_to_pose'] == default['/follow_path'] == 10.0
    assert default['/navigate_to_pose'] == 900.0
    assert set(timeouts('--ros-args', '-p', 'action_server_result_timeout:=3.0').values()) == {3.0}
