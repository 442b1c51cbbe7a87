"""`rclcpp_components component_container`: an empty node under the container's name (the
package docstring says why it loads nothing)."""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node


def main(args=None):
    try:
        with zros.init(args=args):
            node = Node('ComponentManager')   # launch files rename it (name='nav2_container')
            node.get_logger().info('zros runs composable nodes as processes of their own; '
                                   'this container holds none')
            zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
