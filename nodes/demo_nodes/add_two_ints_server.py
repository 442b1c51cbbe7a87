"""The ROS 2 service demo server: answers /add_two_ints (example_interfaces/srv/AddTwoInts)."""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.example_interfaces.srv import AddTwoInts


class AddTwoIntsServer(Node):

    def __init__(self):
        super().__init__('add_two_ints_server')
        self.srv = self.create_service(AddTwoInts, 'add_two_ints', self.add_two_ints_callback)

    def add_two_ints_callback(self, request, response):
        response.sum = request.a + request.b
        self.get_logger().info('Incoming request\na: %d b: %d' % (request.a, request.b))
        return response


def main(args=None):
    zros.init(args=args)
    node = AddTwoIntsServer()
    try:
        zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        zros.try_shutdown()


if __name__ == '__main__':
    main(sys.argv)
