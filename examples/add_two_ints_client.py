"""Call example_interfaces/srv/AddTwoInts once and print the sum.

    python examples/add_two_ints_client.py 3 4   # Result of add_two_ints: for 3 + 4 = 7

Start examples/add_two_ints_server.py (or `zros run demo_nodes add_two_ints_server`) first.
"""
from __future__ import annotations

import argparse
import sys

import zros
from zros.node import Node

from interfaces.example_interfaces.srv import AddTwoInts

from common import parse_args, run


def main(a: int, b: int, service: str, timeout: float, ros_args: list[str]) -> int:
    with zros.init(args=ros_args), Node('add_two_ints_client') as node:
        client = node.create_client(AddTwoInts, service)
        if not client.wait_for_service(timeout_sec=timeout):
            print(f"add_two_ints_client: service '{service}' not available after {timeout:g} s", file=sys.stderr)
            return 1
        # A blocking call needs no spinning: the reply is read on this thread.
        response = client.call(AddTwoInts.Request(a=a, b=b), timeout_sec=timeout)
        if response is None:   # rclpy's answer to a timeout
            print(f"add_two_ints_client: no answer from '{service}' within {timeout:g} s", file=sys.stderr)
            return 1
        node.get_logger().info(f'Result of add_two_ints: for {a} + {b} = {response.sum}')
    return 0


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='add_two_ints_client', description='Call AddTwoInts once.')
    parser.add_argument('a', type=int)
    parser.add_argument('b', type=int)
    parser.add_argument('--service', default='add_two_ints', help='service name (default: add_two_ints)')
    parser.add_argument('--timeout', type=float, default=10.0, help='wait for the server and its reply [s]')
    args = parse_args(parser)
    run(main, args.a, args.b, args.service, args.timeout)
