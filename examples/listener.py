"""Print every std_msgs/String that arrives on a topic, as ROS 2's listener does.

    python examples/listener.py                  # /chatter, until Ctrl-C
    python examples/listener.py --count 3        # exit after three messages

Pair it with examples/talker.py, or feed it with `zros topic pub /chatter std_msgs/msg/String "{data: hi}"`.
"""
from __future__ import annotations

import argparse

import zros
from zros.node import Node

from interfaces.std_msgs.msg import String

from common import parse_args, run


def main(topic: str, count: int, ros_args: list[str]) -> None:
    with zros.init(args=ros_args), Node('listener') as node:
        heard: list[str] = []

        def on_message(message: String) -> None:   # runs on this thread, inside spin_once
            node.get_logger().info(f'I heard: [{message.data}]')
            heard.append(message.data)

        node.create_subscription(String, topic, on_message, 10)   # the node keeps it alive
        while zros.ok() and not (count and len(heard) >= count):
            zros.spin_once(node, timeout_sec=0.5)


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='listener', description='Print std_msgs/String messages.')
    parser.add_argument('--topic', default='chatter', help='topic to listen on (default: chatter)')
    parser.add_argument('--count', type=int, default=0, help='messages to print, then exit (default: 0, forever)')
    args = parse_args(parser)
    run(main, args.topic, args.count)
