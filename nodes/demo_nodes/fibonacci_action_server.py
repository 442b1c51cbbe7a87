"""The ROS 2 action tutorial's server: computes a Fibonacci sequence with feedback per step.

Runs on a MultiThreadedExecutor so that cancel requests and new goals are handled while a
goal executes. The `step_period` parameter is the pause between steps (default 0.5 s).

`/fibonacci` answers goals of both Fibonacci types in use: action_tutorials_interfaces' (the
Humble/Jazzy tutorials; feedback `partial_sequence`) and example_interfaces' (today's tutorials;
feedback `sequence`).
"""
import sys
import time

import zros
from zros.action import ActionServer, CancelResponse, GoalResponse
from zros.callback_groups import ReentrantCallbackGroup
from zros.executors import ExternalShutdownException, MultiThreadedExecutor
from zros.node import Node

from interfaces.action_tutorials_interfaces.action import Fibonacci
from interfaces.example_interfaces.action import Fibonacci as ExampleFibonacci


class FibonacciActionServer(Node):

    def __init__(self):
        super().__init__('fibonacci_action_server')
        self.declare_parameter('step_period', 0.5)
        group = ReentrantCallbackGroup()
        self._action_servers = [
            ActionServer(self, action_type, 'fibonacci', self.execute_callback, callback_group=group,
                         goal_callback=self.goal_callback, cancel_callback=self.cancel_callback)
            for action_type in (Fibonacci, ExampleFibonacci)]

    def goal_callback(self, goal_request):
        if goal_request.order < 0:
            self.get_logger().info('Rejecting goal with negative order')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def cancel_callback(self, goal_handle):
        self.get_logger().info('Received cancel request')
        return CancelResponse.ACCEPT

    def execute_callback(self, goal_handle):
        self.get_logger().info('Executing goal...')
        action_type = ExampleFibonacci if type(goal_handle.request) is ExampleFibonacci.Goal else Fibonacci
        field = 'sequence' if action_type is ExampleFibonacci else 'partial_sequence'
        feedback_msg = action_type.Feedback()
        sequence = [0, 1]
        period = self.get_parameter('step_period').value
        for i in range(1, goal_handle.request.order):
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                self.get_logger().info('Goal canceled')
                return action_type.Result()
            sequence.append(sequence[i] + sequence[i - 1])
            setattr(feedback_msg, field, sequence)
            self.get_logger().info('Feedback: {0}'.format(sequence))
            goal_handle.publish_feedback(feedback_msg)
            time.sleep(period)
        goal_handle.succeed()
        result = action_type.Result()
        result.sequence = sequence[:goal_handle.request.order + 1]
        return result


def main(args=None):
    try:
        with zros.init(args=args):
            node = FibonacciActionServer()
            zros.spin(node, executor=MultiThreadedExecutor())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
