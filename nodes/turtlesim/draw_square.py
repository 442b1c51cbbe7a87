"""draw_square: ROS 2 turtlesim's demo that resets the sim and drives turtle1 in 2 m squares.

A state machine run every 16 ms on turtle1's pose: forward 2 m at 1 m/s, stop, turn 90
degrees at 0.4 rad/s, stop, and again. Logs "New goal [x y, theta]" and "Reached goal" as
ROS's draw_square does.
"""
from __future__ import annotations

import enum
import math
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.geometry_msgs.msg import Twist
from interfaces.std_srvs.srv import Empty
from interfaces.turtlesim.msg import Pose

__all__ = ['DrawSquare', 'main']

PI = 3.141592  # the demo's own constant


class State(enum.Enum):
    FORWARD = 0
    STOP_FORWARD = 1
    TURN = 2
    STOP_TURN = 3


class DrawSquare(Node):

    def __init__(self) -> None:
        super().__init__('draw_square', parameter_event_qos_overrides=True)   # a C++ node in ROS
        self.pose: Pose | None = None
        self.goal = Pose()
        self.state = State.FORWARD
        self.first_goal_set = False
        self.twist_pub = self.create_publisher(Twist, 'turtle1/cmd_vel', 1)
        self.reset = self.create_client(Empty, 'reset')

    def start(self, reset_timeout_sec: float = 10.0) -> None:
        """Reset turtlesim, as the demo does, then follow turtle1's pose every 16 ms.

        Unlike ROS's demo (which sends the reset and goes on), this waits for the reset to be
        done before it subscribes, so a pose from before the reset can never set the first goal.
        """
        if not self.reset.wait_for_service(timeout_sec=reset_timeout_sec):
            self.get_logger().warn("service 'reset' is not available; drawing from where turtle1 is")
        else:
            try:
                self.reset.call(Empty.Request(), timeout_sec=reset_timeout_sec)
            except Exception as exc:  # noqa: BLE001 - draw anyway, from wherever turtle1 is
                self.get_logger().warn(f'reset failed ({exc}); drawing from where turtle1 is')
        self.create_subscription(Pose, 'turtle1/pose', self._on_pose, 1)
        self.create_timer(0.016, self._on_timer)

    def _on_pose(self, pose: Pose) -> None:
        self.pose = pose

    def _reached_goal(self) -> bool:
        p, g = self.pose, self.goal
        return abs(p.x - g.x) < 0.1 and abs(p.y - g.y) < 0.1 and abs(p.theta - g.theta) < 0.01

    def _stopped(self) -> bool:
        return self.pose.angular_velocity < 0.0001 and self.pose.linear_velocity < 0.0001

    def _print_goal(self) -> None:
        self.get_logger().info(f'New goal [{self.goal.x:f} {self.goal.y:f}, {self.goal.theta:f}]')

    def _command(self, linear: float, angular: float) -> None:
        twist = Twist()
        twist.linear.x = linear
        twist.angular.z = angular
        self.twist_pub.publish(twist)

    def _goal_ahead(self) -> None:
        self.goal.x = math.cos(self.pose.theta) * 2 + self.pose.x
        self.goal.y = math.sin(self.pose.theta) * 2 + self.pose.y
        self.goal.theta = self.pose.theta

    def _on_timer(self) -> None:
        if self.pose is None:
            return
        if not self.first_goal_set:
            self.first_goal_set = True
            self.state = State.FORWARD
            self._goal_ahead()
            self._print_goal()
        if self.state == State.FORWARD:
            if self._reached_goal():
                self.state = State.STOP_FORWARD
                self._command(0.0, 0.0)
            else:
                self._command(1.0, 0.0)
        elif self.state == State.STOP_FORWARD:
            if self._stopped():
                self.get_logger().info('Reached goal')
                self.state = State.TURN
                self.goal.x, self.goal.y = self.pose.x, self.pose.y
                theta = math.fmod(self.pose.theta + PI / 2.0, 2 * PI)
                if theta >= PI:  # wrap to [-pi, pi)
                    theta -= 2 * PI
                self.goal.theta = theta
                self._print_goal()
            else:
                self._command(0.0, 0.0)
        elif self.state == State.TURN:
            if self._reached_goal():
                self.state = State.STOP_TURN
                self._command(0.0, 0.0)
            else:
                self._command(0.0, 0.4)
        elif self.state == State.STOP_TURN:
            if self._stopped():
                self.get_logger().info('Reached goal')
                self.state = State.FORWARD
                self._goal_ahead()
                self._print_goal()
            else:
                self._command(0.0, 0.0)


def main(args: list[str] | None = None) -> None:
    try:
        with zros.init(args=args):
            node = DrawSquare()
            node.start()
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
