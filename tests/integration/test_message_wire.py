"""Messages on the wire between processes and sessions (the codec itself:
tests/unit/test_message.py)."""
from __future__ import annotations

import array
import threading
import time

import msgpack

from unit.test_message import custom_package  # noqa: F401 - the fixture
from zros.keys import topic_key
from zros.node import Node

from interfaces.geometry_msgs.msg import Point, Twist, Vector3

FIBONACCI_SERVER = '''
import time
import zros
from zros.action import ActionServer
from zros.node import Node
from interfaces.action_tutorials_interfaces.action import Fibonacci


class FibonacciActionServer(Node):
    """The ROS 2 tutorial's server, ported by the README's two edits: it appends to the
    feedback's sequence and hands that sequence to the result."""

    def __init__(self):
        super().__init__('fibonacci_action_server')
        self._action_server = ActionServer(self, Fibonacci, 'fibonacci', self.execute_callback)

    def execute_callback(self, goal_handle):
        feedback_msg = Fibonacci.Feedback()
        feedback_msg.partial_sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            feedback_msg.partial_sequence.append(
                feedback_msg.partial_sequence[i] + feedback_msg.partial_sequence[i - 1])
            goal_handle.publish_feedback(feedback_msg)
            time.sleep(0.01)
        goal_handle.succeed()
        result = Fibonacci.Result()
        result.sequence = feedback_msg.partial_sequence
        self.get_logger().info(f'Result: {result.sequence}')
        return result


zros.init()
node = FibonacciActionServer()
print('ready', flush=True)
zros.spin(node)
'''


def test_plain_msgpack_decodes_what_zros_sends(context, raw_session):
    """A raw zenoh-python subscriber and the `msgpack` package read a zros topic."""
    key = topic_key(context.domain_id, '/plain')
    samples = []
    arrived = threading.Event()

    def on_sample(sample):
        samples.append((sample.payload.to_bytes(),
                        sample.attachment.to_bytes() if sample.attachment is not None else None))
        arrived.set()
    subscriber = raw_session.declare_subscriber(key, on_sample)
    node = Node('plain_pub', context=context)
    publisher = node.create_publisher(Twist, '/plain', 10)
    deadline = time.monotonic() + 5
    while not arrived.is_set() and time.monotonic() < deadline:
        publisher.publish(Twist(linear=Vector3(x=1.0, y=-2.0), angular=Vector3(z=0.5)))
        arrived.wait(0.05)
    subscriber.undeclare()
    assert samples, 'the raw subscriber got nothing'
    payload, attachment = samples[0]
    assert msgpack.unpackb(payload) == [[1.0, -2.0, 0.0], [0.0, 0.0, 0.5]]
    # the attachment names the type (protocol v2): magic, gid, seq, time, hash, type name
    assert attachment.startswith(b'Z2')
    assert attachment.endswith(b'geometry_msgs/msg/Twist')
    assert bytes.fromhex(Twist._HASH) in attachment


def test_custom_message_over_the_wire(make_context, custom_package, spin_for):
    """A custom type is usable on a topic between two sessions."""
    import importlib
    from zros.executors import SingleThreadedExecutor
    Custom = importlib.import_module(f'interfaces.{custom_package}.msg').Custom
    pub_ctx, sub_ctx = make_context(), make_context()
    node = Node('custom_sub', context=sub_ctx)
    received = []
    node.create_subscription(Custom, '/custom', received.append, 10)
    executor = SingleThreadedExecutor(context=sub_ctx)
    executor.add_node(node)
    publisher = Node('custom_pub', context=pub_ctx).create_publisher(Custom, '/custom', 10)
    assert publisher.wait_for_subscribers(1, 5.0)
    publisher.publish(Custom(count=-3, tags=['a'], where=Point(z=2.0)))
    spin_for(executor, lambda: received, timeout=5)
    assert received[0] == Custom(count=-3, tags=['a'], where=Point(z=2.0))


def test_canonical_fibonacci_server_that_appends(spawn, context):
    from interfaces.action_tutorials_interfaces.action import Fibonacci
    from zros.action import ActionClient
    server = spawn.script(FIBONACCI_SERVER, name='fibonacci_append')
    server.wait_for_output('ready', timeout=15)
    node = Node('fib_client', context=context)
    client = ActionClient(node, Fibonacci, 'fibonacci')
    assert client.wait_for_server(timeout_sec=10), server.output()
    result = client.send_goal(Fibonacci.Goal(order=7))
    assert result is not None and result.status == 4, server.output()  # SUCCEEDED
    assert result.result.sequence == array.array('i', [0, 1, 1, 2, 3, 5, 8, 13])
    server.wait_for_output("Result: array('i', [0, 1, 1, 2, 3, 5, 8, 13])", timeout=5)
    assert 'Traceback' not in server.output()
