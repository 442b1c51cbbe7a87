"""Actions with code written against ROS 2's action protocol: services and topics made from an
action's `Impl` types, goal ids chosen by the client, and one shared feedback topic."""
from __future__ import annotations

import time
import uuid

import pytest

from zros.action import ActionClient, ActionServer, GoalStatus
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.testing import spin_until

from interfaces.action_msgs.msg import GoalInfo
from interfaces.example_interfaces.action import Fibonacci
from interfaces.unique_identifier_msgs.msg import UUID


def _new_id() -> UUID:
    return UUID(uuid=list(uuid.uuid4().bytes))


@pytest.fixture
def node_and_executor(context):
    node = Node('ros2_protocol', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    yield node, executor
    executor.shutdown()
    node.destroy_node()


class PlainClient:
    """An action client made of plain entities from `Impl`, speaking ROS 2's protocol."""

    def __init__(self, node, name):
        self.send_goal = node.create_client(Fibonacci.Impl.SendGoalService, f'{name}/_action/send_goal')
        self.cancel = node.create_client(Fibonacci.Impl.CancelGoalService, f'{name}/_action/cancel_goal')
        self.get_result = node.create_client(Fibonacci.Impl.GetResultService, f'{name}/_action/get_result')
        self.feedback = []
        node.create_subscription(Fibonacci.Impl.FeedbackMessage, f'{name}/_action/feedback',
                                 self.feedback.append, 10)
        for client in (self.send_goal, self.cancel, self.get_result):
            assert client.wait_for_service(timeout_sec=10)

    def call(self, executor, client, request):
        future = client.call_async(request)
        executor.spin_until_future_complete(future, timeout_sec=10)
        return future.result()

    def goal(self, executor, goal_id, order=3):
        request = Fibonacci.Impl.SendGoalService.Request()
        request.goal_id = goal_id
        request.goal.order = order
        return self.call(executor, self.send_goal, request)


def test_server_keeps_the_goal_id_the_client_chose_and_rejects_it_twice(node_and_executor):
    node, executor = node_and_executor
    seen = []

    def execute(handle):
        handle.publish_feedback(Fibonacci.Feedback(sequence=[handle.request.order]))
        handle.succeed()
        return Fibonacci.Result(sequence=[1, 2])
    server = ActionServer(node, Fibonacci, '/plain', execute, handle_accepted_callback=lambda h: (seen.append(h),
                                                                                                  h.execute()))
    plain = PlainClient(node, '/plain')
    goal_id = _new_id()
    assert plain.goal(executor, goal_id).accepted
    # the accepted-callback had run when the reply came, and the goal has the client's id
    assert len(seen) == 1 and list(seen[0].goal_id.uuid) == list(goal_id.uuid)
    assert not plain.goal(executor, goal_id).accepted  # the same id again
    result = plain.call(executor, plain.get_result, Fibonacci.Impl.GetResultService.Request(goal_id=goal_id))
    assert result.status == GoalStatus.SUCCEEDED and result.result.sequence.tolist() == [1, 2]
    # a goal sent without a client id gets its feedback on the shared topic
    spin_until(executor, lambda: plain.feedback, timeout=5)
    assert list(plain.feedback[0].goal_id.uuid) == list(goal_id.uuid)
    assert plain.feedback[0].feedback.sequence.tolist() == [3]
    assert len(seen) == 1
    server.destroy()


def test_cancel_by_the_client_chosen_id(node_and_executor):
    node, executor = node_and_executor
    from zros.action import CancelResponse
    server = ActionServer(node, Fibonacci, '/plain', lambda h: Fibonacci.Result(),
                          handle_accepted_callback=lambda h: None, cancel_callback=lambda h: CancelResponse.ACCEPT)
    plain = PlainClient(node, '/plain')
    goal_id = _new_id()
    assert plain.goal(executor, goal_id).accepted
    answer = plain.call(executor, plain.cancel, Fibonacci.Impl.CancelGoalService.Request(
        goal_info=GoalInfo(goal_id=goal_id)))
    assert [list(info.goal_id.uuid) for info in answer.goals_canceling] == [list(goal_id.uuid)]
    server.destroy()


def test_finished_results_expire_while_the_node_spins(node_and_executor):
    node, executor = node_and_executor

    def execute(handle):
        handle.succeed()
        return Fibonacci.Result()
    server = ActionServer(node, Fibonacci, '/plain', execute, result_timeout=0.3)
    plain = PlainClient(node, '/plain')
    goal_id = _new_id()
    assert plain.goal(executor, goal_id).accepted
    request = Fibonacci.Impl.GetResultService.Request(goal_id=goal_id)
    assert plain.call(executor, plain.get_result, request).status == GoalStatus.SUCCEEDED
    deadline = time.monotonic() + 1.0
    while time.monotonic() < deadline:  # only the expiry timer runs: no status change happens
        executor.spin_once(timeout_sec=0.05)
    assert plain.call(executor, plain.get_result, request).status == GoalStatus.UNKNOWN
    server.destroy()


class PlainServer:
    """An action server made of plain entities from `Impl`: its replies carry no goal id, and it
    publishes feedback on the shared topic."""

    def __init__(self, node, name):
        node.create_service(Fibonacci.Impl.SendGoalService, f'{name}/_action/send_goal', self.on_goal)
        node.create_service(Fibonacci.Impl.CancelGoalService, f'{name}/_action/cancel_goal',
                            lambda request, response: response)
        node.create_service(Fibonacci.Impl.GetResultService, f'{name}/_action/get_result', self.on_result)
        self.feedback = node.create_publisher(Fibonacci.Impl.FeedbackMessage, f'{name}/_action/feedback', 10)

    def on_goal(self, request, response):
        response.accepted = True
        return response

    def on_result(self, request, response):
        response.status = GoalStatus.SUCCEEDED
        return response

    def publish(self, goal_id, order):
        self.feedback.publish(Fibonacci.Impl.FeedbackMessage(goal_id=goal_id,
                                                             feedback=Fibonacci.Feedback(sequence=[order])))


def test_client_keeps_its_goal_id_and_hears_the_shared_feedback_topic_until_the_result(node_and_executor):
    node, executor = node_and_executor
    server = PlainServer(node, '/bare')
    client = ActionClient(node, Fibonacci, '/bare')
    assert client.wait_for_server(timeout_sec=10)  # no ActionServer: its three services suffice
    heard = []
    goal_id = _new_id()
    future = client.send_goal_async(Fibonacci.Goal(), feedback_callback=heard.append, goal_uuid=goal_id)
    executor.spin_until_future_complete(future, timeout_sec=10)
    handle = future.result()
    assert handle.accepted and list(handle.goal_id.uuid) == list(goal_id.uuid)
    server.publish(_new_id(), 1)  # another goal's feedback
    server.publish(goal_id, 2)
    spin_until(executor, lambda: heard, timeout=5)
    assert [m.feedback.sequence.tolist() for m in heard] == [[2]]
    result = handle.get_result_async()
    executor.spin_until_future_complete(result, timeout_sec=10)
    assert result.result().status == GoalStatus.SUCCEEDED
    server.publish(goal_id, 3)  # after the result: dropped, as rclpy drops it
    deadline = time.monotonic() + 0.5
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    assert [m.feedback.sequence.tolist() for m in heard] == [[2]]
    client.destroy()


def test_feedback_sent_before_a_goal_is_not_delivered(node_and_executor):
    node, executor = node_and_executor
    server = PlainServer(node, '/bare')
    client = ActionClient(node, Fibonacci, '/bare')
    assert client.wait_for_server(timeout_sec=10)
    goal_id = _new_id()
    server.publish(goal_id, 1)
    deadline = time.monotonic() + 0.5
    while time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    heard = []
    future = client.send_goal_async(Fibonacci.Goal(), feedback_callback=heard.append, goal_uuid=goal_id)
    executor.spin_until_future_complete(future, timeout_sec=10)
    assert future.result().accepted and heard == []
    client.destroy()


def test_entity_counts_are_rclpys(node_and_executor):
    node, _ = node_and_executor
    client = ActionClient(node, Fibonacci, '/counted')
    server = ActionServer(node, Fibonacci, '/counted', lambda h: Fibonacci.Result())
    assert tuple(client.get_num_entities())[:5] == (2, 0, 0, 3, 0)
    assert tuple(server.get_num_entities())[:5] == (0, 0, 1, 0, 3)
    client.destroy()
    server.destroy()
