"""`demo_nodes_py talker_qos`: the talker with a chosen reliability that stops after a number of
cycles (ROS 2's demo of the same name; launch_ros's tests start it with `--number_of_cycles 1`).

    zros run demo_nodes_py talker_qos [--reliable] [-n CYCLES]

Best effort unless `--reliable`; one 'Hello World: N' on /chatter per second, `CYCLES` times
(20 by default), then it exits.
"""
import argparse
import sys
from typing import Callable

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node
from zros.qos import QoSProfile, QoSReliabilityPolicy
from zros.utilities import remove_ros_args

from interfaces.std_msgs.msg import String

#: [s] between messages
PERIOD = 1.0


def qos_profile(reliable: bool) -> QoSProfile:
    """Depth 10, reliable or best effort as asked (shared with listener_qos)."""
    policy = QoSReliabilityPolicy.RELIABLE if reliable else QoSReliabilityPolicy.BEST_EFFORT
    return QoSProfile(depth=10, reliability=policy)


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    """`--reliable` and `-n/--number_of_cycles`, after the ROS arguments are taken out."""
    parser = argparse.ArgumentParser()
    parser.add_argument('--reliable', action='store_true', help='reliable QoS instead of best effort')
    parser.add_argument('-n', '--number_of_cycles', type=int, default=20, help='how many cycles to run')
    return parser.parse_args(remove_ros_args(args=argv)[1:])


def run_cycles(make_node: Callable[[QoSProfile], Node], args: list[str] | None) -> None:
    """Parse the options, make the node with the QoS they ask for, spin it `number_of_cycles`
    times (talker_qos and listener_qos alike)."""
    argv = sys.argv if args is None else args
    options = parse_arguments(argv)
    try:
        with zros.init(args=argv):
            node = make_node(qos_profile(options.reliable))
            for _ in range(options.number_of_cycles):
                zros.spin_once(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


class TalkerQos(Node):
    """Publishes 'Hello World: N' with a sequence number, one per timer tick."""

    def __init__(self, qos: QoSProfile):
        super().__init__('talker_qos')
        self.sent = 0
        self.pub = self.create_publisher(String, 'chatter', qos)
        self.tmr = self.create_timer(PERIOD, self.publish_next)

    def publish_next(self):
        self.sent += 1
        text = f'Hello World: {self.sent}'
        self.get_logger().info(f"Publishing: '{text}'")
        self.pub.publish(String(data=text))


def main(args=None):
    run_cycles(TalkerQos, args)


if __name__ == '__main__':
    main(sys.argv)
