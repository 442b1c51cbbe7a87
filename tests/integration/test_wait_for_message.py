"""rclpy.wait_for_message, and the endpoint getters rclpy's publisher and subscription tests use."""
from __future__ import annotations

import threading

import pytest

from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.wait_for_message import wait_for_message

from interfaces.std_msgs.msg import String


def _publish_when_heard(node: Node, topic: str, text: str) -> threading.Thread:
    publisher = node.create_publisher(String, topic, 10)

    def run() -> None:
        while node.count_subscribers(topic) == 0:
            threading.Event().wait(0.02)
        publisher.publish(String(data=text))
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


def test_waits_for_one_message_and_unsubscribes(context):
    node = Node('waiter', context=context)
    thread = _publish_when_heard(node, 'greeting', 'hello')
    ok, msg = wait_for_message(String, node, 'greeting', qos_profile=10, time_to_wait=5.0)
    thread.join(5.0)
    assert ok and msg.data == 'hello'
    assert node.count_subscribers('greeting') == 0 and node.executor is None
    node.destroy_node()


def test_times_out_with_false(context):
    node = Node('patient', context=context)
    assert wait_for_message(String, node, 'silence', time_to_wait=0.2) == (False, None)
    node.destroy_node()


def test_a_node_spun_elsewhere_is_not_spun_again(context):
    node = Node('busy', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    thread = _publish_when_heard(node, 'news', 'spun')
    ok, msg = wait_for_message(String, node, 'news', time_to_wait=5.0)
    thread.join(5.0)
    assert ok and msg.data == 'spun' and node.executor is executor
    executor.shutdown()
    spinner.join(5.0)
    node.destroy_node()


def test_endpoint_counts_and_acks_from_either_side(context, wait_for):
    node = Node('counter', context=context)
    subscription = node.create_subscription(String, 'counted', lambda _: None, 10)
    assert subscription.get_publisher_count() == 0
    publisher = node.create_publisher(String, 'counted', 10)
    wait_for(lambda: subscription.get_publisher_count() == 1)
    publisher.publish(String(data='x'))
    assert publisher.wait_for_all_acked()   # Zenoh gives no acks: reliable publish already blocked
    publisher.destroy()
    with pytest.raises(RuntimeError):
        publisher.wait_for_all_acked()
    node.destroy_node()
