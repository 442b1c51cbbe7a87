"""The ROS 2 talker demo: publishes 'Hello World: N' on /chatter once a second.

Written as rclpy tutorial code with the two mechanical edits (rclpy -> zros, std_msgs ->
interfaces.std_msgs), which is the point: it shows the porting story works.
"""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.std_msgs.msg import String


class Talker(Node):

    def __init__(self):
        super().__init__('talker')
        self.i = 0
        self.pub = self.create_publisher(String, 'chatter', 10)
        timer_period = 1.0
        self.tmr = self.create_timer(timer_period, self.timer_callback)

    def timer_callback(self):
        self.i += 1
        msg = String()
        msg.data = 'Hello World: {0}'.format(self.i)
        self.get_logger().info("Publishing: '{0}'".format(msg.data))
        self.pub.publish(msg)


def main(args=None):
    try:
        with zros.init(args=args):
            node = Talker()
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
