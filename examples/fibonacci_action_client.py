"""Send one Fibonacci goal, print its feedback as it comes and its result.

    python examples/fibonacci_action_client.py 5      # Result: [0, 1, 1, 2, 3, 5]

Start the server first: `zros run demo_nodes fibonacci_action_server`.
"""
from __future__ import annotations

import argparse
import sys
from typing import Any

import zros
from zros.action import ActionClient
from zros.node import Node

from interfaces.action_tutorials_interfaces.action import Fibonacci

from common import parse_args, run


def main(order: int, action: str, timeout: float, ros_args: list[str]) -> int:
    with zros.init(args=ros_args), Node('fibonacci_action_client') as node:
        client = ActionClient(node, Fibonacci, action)
        if not client.wait_for_server(timeout_sec=timeout):
            print(f"fibonacci_action_client: action '{action}' not available after {timeout:g} s", file=sys.stderr)
            return 1

        def on_feedback(feedback_message: Any) -> None:   # Fibonacci's FeedbackMessage: goal_id, feedback
            node.get_logger().info(f'Received feedback: {list(feedback_message.feedback.partial_sequence)}')

        # Futures complete while the node spins, so feedback callbacks run meanwhile.
        sent = client.send_goal_async(Fibonacci.Goal(order=order), feedback_callback=on_feedback)
        zros.spin_until_future_complete(node, sent, timeout_sec=timeout)
        goal = sent.result()
        if goal is None or not goal.accepted:
            print('fibonacci_action_client: goal rejected', file=sys.stderr)
            return 1
        finished = goal.get_result_async()
        zros.spin_until_future_complete(node, finished)
        node.get_logger().info(f'Result: {list(finished.result().result.sequence)}')
    return 0


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='fibonacci_action_client', description='Send one Fibonacci goal.')
    parser.add_argument('order', type=int, nargs='?', default=10, help='how many numbers (default: 10)')
    parser.add_argument('--action', default='fibonacci', help='action name (default: fibonacci)')
    parser.add_argument('--timeout', type=float, default=10.0, help='wait for the server and the acceptance [s]')
    args = parse_args(parser)
    run(main, args.order, args.action, args.timeout)
