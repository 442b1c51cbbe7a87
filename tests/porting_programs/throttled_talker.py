"""A callback group of one's own (rclpy's extension point): a token bucket that lets a fast
timer run only as often as tokens are refilled."""
import threading

import rclpy
from rclpy.callback_groups import CallbackGroup
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class TokenBucketGroup(CallbackGroup):
    def __init__(self, node, tokens):
        super().__init__()
        self.tokens = tokens
        self.lock = threading.Lock()
        node.create_timer(0.5, self.refill)

    def can_execute(self, entity):
        return self.tokens > 0

    def beginning_execution(self, entity):
        with self.lock:
            if self.tokens > 0:
                self.tokens -= 1
                return True
            return False

    def ending_execution(self, entity):
        pass

    def refill(self):
        with self.lock:
            self.tokens += 1


class ThrottledTalker(Node):
    def __init__(self):
        super().__init__('throttled_talker')
        self.count = 0
        self.pub = self.create_publisher(String, 'throttled', 10)
        self.create_timer(0.01, self.tick, callback_group=TokenBucketGroup(self, tokens=3))

    def tick(self):
        self.count += 1
        self.pub.publish(String(data=f'tick {self.count}'))
        self.get_logger().info(f'tick {self.count}')


def main():
    try:
        with rclpy.init():
            rclpy.spin(ThrottledTalker())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == '__main__':
    main()
