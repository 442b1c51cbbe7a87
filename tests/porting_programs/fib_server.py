"""A Fibonacci action server as the ROS 2 tutorials write it: the feedback sequence grows by
append, and goals run in parallel on a multi-threaded executor."""
import time

import rclpy
from action_tutorials_interfaces.action import Fibonacci
from rclpy.action import ActionServer
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node


class FibServer(Node):
    def __init__(self):
        super().__init__('fib_server')
        ActionServer(self, Fibonacci, 'fib', self.execute, callback_group=ReentrantCallbackGroup())

    def execute(self, goal_handle):
        feedback = Fibonacci.Feedback()
        feedback.partial_sequence = [0, 1]
        for _ in range(goal_handle.request.order - 1):
            feedback.partial_sequence.append(feedback.partial_sequence[-1] + feedback.partial_sequence[-2])
            goal_handle.publish_feedback(feedback)
            time.sleep(0.02)
        goal_handle.succeed()
        result = Fibonacci.Result()
        result.sequence = feedback.partial_sequence
        return result


def main():
    try:
        with rclpy.init():
            rclpy.spin(FibServer(), executor=MultiThreadedExecutor())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main()
