"""An action class's protocol types, reached as rclpy code does through `Name.Impl`."""
from __future__ import annotations

from zros.action.counts import NumberOfEntities
from zros.message import deserialize, serialize

from interfaces.action_msgs.msg import GoalStatusArray
from interfaces.action_msgs.srv import CancelGoal
from interfaces.example_interfaces.action import Fibonacci
from interfaces.unique_identifier_msgs.msg import UUID


def test_impl_names_the_five_protocol_types():
    impl = Fibonacci.Impl
    assert impl.SendGoalService._TYPE == 'example_interfaces/action/Fibonacci_SendGoal'
    assert impl.GetResultService._TYPE == 'example_interfaces/action/Fibonacci_GetResult'
    assert impl.FeedbackMessage._TYPE == 'example_interfaces/action/Fibonacci_FeedbackMessage'
    assert impl.CancelGoalService is CancelGoal
    assert impl.GoalStatusMessage is GoalStatusArray


def test_impl_is_built_once_per_action_class():
    assert Fibonacci.Impl is Fibonacci.Impl
    assert Fibonacci().Impl is Fibonacci.Impl


def test_send_goal_request_carries_the_goal_id_beside_the_goal_and_client_id():
    """ROS 2 code fills `goal_id` and `goal`; zros clients add their client id. An unset id is
    all zeros: the server then picks one."""
    request = Fibonacci.Impl.SendGoalService.Request()
    assert not any(request.goal_id.uuid) and request.client_id == ''
    request.goal_id = UUID(uuid=list(range(16)))
    request.goal.order = 7
    decoded = deserialize(serialize(request), Fibonacci.Impl.SendGoalService.Request)
    assert list(decoded.goal_id.uuid) == list(range(16)) and decoded.goal.order == 7
    response = Fibonacci.Impl.SendGoalService.Response()
    assert response.accepted is False and hasattr(response, 'goal_id') and hasattr(response, 'stamp')


def test_result_and_feedback_types_wrap_the_action_parts():
    assert type(Fibonacci.Impl.GetResultService.Response().result) is Fibonacci.Result
    assert type(Fibonacci.Impl.FeedbackMessage().feedback) is Fibonacci.Feedback


def test_number_of_entities_counts_default_to_zero():
    counts = NumberOfEntities(num_services=3, num_timers=1)
    assert (counts.num_subscriptions, counts.num_guard_conditions, counts.num_clients, counts.num_events) == (0, 0, 0, 0)
    assert (counts.num_services, counts.num_timers) == (3, 1)
