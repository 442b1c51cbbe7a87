"""mimic: ROS 2 turtlesim's turtle_mimic, which makes one turtle copy another's motion.

Subscribes to `input/pose` (turtlesim/msg/Pose) and publishes on `output/cmd_vel` a Twist with
the pose's linear and angular velocity. Remap both to connect two turtles, e.g.
`--ros-args -r /input/pose:=/turtlesim1/turtle1/pose -r /output/cmd_vel:=/turtlesim2/turtle1/cmd_vel`
(configs/turtlesim_mimic.launch.yaml does this).
"""
from __future__ import annotations

import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.geometry_msgs.msg import Twist
from interfaces.turtlesim.msg import Pose

__all__ = ['Mimic', 'main']


class Mimic(Node):

    def __init__(self) -> None:
        super().__init__('turtle_mimic', parameter_event_qos_overrides=True)   # a C++ node in ROS
        self.twist_pub = self.create_publisher(Twist, 'output/cmd_vel', 7)
        self.create_subscription(Pose, 'input/pose', self._on_pose, 7)

    def _on_pose(self, pose: Pose) -> None:
        twist = Twist()
        twist.angular.z = pose.angular_velocity
        twist.linear.x = pose.linear_velocity
        self.twist_pub.publish(twist)


def main(args: list[str] | None = None) -> None:
    try:
        with zros.init(args=args):
            zros.spin(Mimic())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
