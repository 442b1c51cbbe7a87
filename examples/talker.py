"""Publish 'Hello World: N' on a topic, as ROS 2's talker does.

    python examples/talker.py                                 # /chatter, once a second, until Ctrl-C
    python examples/talker.py --topic news --period 0.2 --count 10

Pair it with examples/listener.py, or watch it with `zros topic echo /chatter`.
"""
from __future__ import annotations

import argparse
import itertools

import zros
from zros.node import Node

from interfaces.std_msgs.msg import String

from common import parse_args, run


def main(topic: str, period: float, count: int, ros_args: list[str]) -> None:
    with zros.init(args=ros_args), Node('talker') as node:
        publisher = node.create_publisher(String, topic, 10)
        rate = node.create_rate(1.0 / period)   # sleeps on the node's clock; no spinning needed
        for number in range(1, count + 1) if count else itertools.count(1):
            message = String(data=f'Hello World: {number}')
            node.get_logger().info(f"Publishing: '{message.data}'")
            publisher.publish(message)
            rate.sleep()


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='talker', description='Publish std_msgs/String messages.')
    parser.add_argument('--topic', default='chatter', help='topic to publish on (default: chatter)')
    parser.add_argument('--period', type=float, default=1.0, help='time between messages [s] (default: 1)')
    parser.add_argument('--count', type=int, default=0, help='messages to send, then exit (default: 0, forever)')
    args = parse_args(parser)   # what follows --ros-args is zros's
    if args.period <= 0:
        parser.error('--period must be greater than 0')
    run(main, args.topic, args.period, args.count)
