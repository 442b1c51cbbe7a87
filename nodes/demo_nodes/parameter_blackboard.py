"""The ROS 2 parameter blackboard: a node that holds whatever parameters it is given.

Any parameter may be set on it (`zros param set /parameter_blackboard any_name 1`), and the
`-p`/`--params-file` values it starts with are declared, so other nodes (rclpy's
AsyncParameterClient demo, `zros param load`) have somewhere to keep shared values.
"""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node


class ParameterBlackboard(Node):

    def __init__(self):
        super().__init__('parameter_blackboard', allow_undeclared_parameters=True,
                         automatically_declare_parameters_from_overrides=True)
        count = len(self.get_parameters_by_prefix('')) - 1  # use_sim_time is every node's
        self.get_logger().info(f"Parameter blackboard node named '{self.get_fully_qualified_name()}' ready, "
                               f"and serving '{count}' parameters already!")


def main(args=None):
    try:
        with zros.init(args=args):
            zros.spin(ParameterBlackboard())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main(sys.argv)
