"""The ROS 2 parameter tutorial's talker: publishes `published_text` every `timer_period` s.

Changing `timer_period` at run time re-creates the timer; both parameters are typed and
described, and `timer_period` is range-checked (0.1 .. 10 s).
"""
import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node

from interfaces.rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, SetParametersResult
from interfaces.std_msgs.msg import String


class ParamTalker(Node):

    def __init__(self):
        # allow_undeclared_parameters: `zros param set /param_talker extra 1` adds a parameter.
        super().__init__('param_talker', allow_undeclared_parameters=True)
        self.declare_parameter('published_text', 'Hello World',
                               ParameterDescriptor(description='Text published on /chatter'))
        self.declare_parameter('timer_period', 1.0, ParameterDescriptor(
            description='Seconds between messages',
            floating_point_range=[FloatingPointRange(from_value=0.1, to_value=10.0, step=0.0)]))
        self.count = 0
        self.pub = self.create_publisher(String, 'chatter', 10)
        self.timer = self.create_timer(self.get_parameter('timer_period').value, self.on_timer)
        self.add_on_set_parameters_callback(self.on_parameters)

    def on_parameters(self, params):
        for param in params:
            if param.name == 'published_text' and not str(param.value or '').strip():
                return SetParametersResult(successful=False, reason='published_text must not be empty')
        for param in params:
            if param.name == 'timer_period':
                self.destroy_timer(self.timer)
                self.timer = self.create_timer(param.value, self.on_timer)
                self.get_logger().info(f'timer_period is now {param.value} s')
        return SetParametersResult(successful=True)

    def on_timer(self):
        self.count += 1
        text = self.get_parameter('published_text').value
        msg = String(data=f'{text}: {self.count}')
        self.get_logger().info(f"Publishing: '{msg.data}'")
        self.pub.publish(msg)


def main(args=None):
    zros.init(args=args)
    node = ParamTalker()
    try:
        zros.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        zros.try_shutdown()


if __name__ == '__main__':
    main(sys.argv)
