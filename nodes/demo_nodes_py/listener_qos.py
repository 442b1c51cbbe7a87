"""`demo_nodes_py listener_qos`: the listener with a chosen reliability that stops after a
number of cycles (ROS 2's demo of the same name).

    zros run demo_nodes_py listener_qos [--reliable] [-n CYCLES]

Best effort unless `--reliable` (so it hears talker_qos either way); it prints what arrives on
/chatter and exits after `CYCLES` spins (20 by default).
"""
import sys

from zros.node import Node

from interfaces.std_msgs.msg import String
from nodes.demo_nodes_py.talker_qos import run_cycles


class ListenerQos(Node):

    def __init__(self, qos):
        super().__init__('listener_qos')
        self.sub = self.create_subscription(String, 'chatter', self.chatter_callback, qos)

    def chatter_callback(self, msg):
        self.get_logger().info(f'I heard: [{msg.data}]')


def main(args=None):
    run_cycles(ListenerQos, args)


if __name__ == '__main__':
    main(sys.argv)
