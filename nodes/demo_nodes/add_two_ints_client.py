"""The ROS 2 service demo client: `add_two_ints_client A B` asks /add_two_ints for A + B."""
import sys

import zros
from zros.node import Node
from zros.utilities import remove_ros_args

from interfaces.example_interfaces.srv import AddTwoInts


class AddTwoIntsClient(Node):

    def __init__(self):
        super().__init__('add_two_ints_client')
        self.cli = self.create_client(AddTwoInts, 'add_two_ints')
        while not self.cli.wait_for_service(timeout_sec=1.0):
            self.get_logger().info('service not available, waiting again...')
        self.req = AddTwoInts.Request()

    def send_request(self, a, b):
        self.req.a = a
        self.req.b = b
        return self.cli.call_async(self.req)


def main(args=None):
    zros.init(args=args)
    argv = remove_ros_args(sys.argv if args is None else args)
    a, b = (int(argv[1]), int(argv[2])) if len(argv) >= 3 else (2, 3)
    node = AddTwoIntsClient()
    try:
        future = node.send_request(a, b)
        zros.spin_until_future_complete(node, future)
        response = future.result()
        node.get_logger().info('Result of add_two_ints: for %d + %d = %d' % (a, b, response.sum))
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        zros.try_shutdown()


if __name__ == '__main__':
    main(sys.argv)
