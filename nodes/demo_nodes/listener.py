"""The ROS 2 listener demo: prints what arrives on /chatter (rclpy tutorial style)."""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.std_msgs.msg import String


class Listener(Node):

    def __init__(self):
        super().__init__('listener')
        self.sub = self.create_subscription(String, 'chatter', self.chatter_callback, 10)

    def chatter_callback(self, msg):
        self.get_logger().info('I heard: [%s]' % msg.data)


def main(args=None):
    zros.init(args=args)
    node = Listener()
    try:
        zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        zros.try_shutdown()


if __name__ == '__main__':
    main(sys.argv)
