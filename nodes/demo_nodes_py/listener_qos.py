"""`demo_nodes_py listener_qos`: the listener with a chosen reliability that stops after a
number of cycles (ROS 2's demo of the same name).

    zros run demo_nodes_py listener_qos [--reliable] [-n CYCLES]

Best effort unless `--reliable` (so it hears talker_qos either way); it says which, prints what
arrives on /chatter, and exits after `CYCLES` spins (20 by default). Each spin waits for a
message, so with no talker it runs until it is stopped (launch_ros's tests start it and shut
the launch down after a while).
"""
import sys

from zros.node import Node
from zros.qos import QoSProfile, QoSReliabilityPolicy

from interfaces.std_msgs.msg import String
from nodes.demo_nodes_py.talker_qos import run_cycles


class ListenerQos(Node):
    """Logs every String heard on 'chatter'."""

    def __init__(self, qos: QoSProfile):
        super().__init__('listener_qos')
        reliable = qos.reliability == QoSReliabilityPolicy.RELIABLE
        self.get_logger().info('Reliable listener' if reliable else 'Best effort listener')
        self.sub = self.create_subscription(String, 'chatter', self.chatter_callback, qos)

    def chatter_callback(self, msg):
        self.get_logger().info(f'I heard: [{msg.data}]')


def main(args=None):
    run_cycles(ListenerQos, args)


if __name__ == '__main__':
    main(sys.argv)
