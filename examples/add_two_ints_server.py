"""Serve example_interfaces/srv/AddTwoInts: answer each request with the sum of a and b.

    python examples/add_two_ints_server.py       # /add_two_ints, until Ctrl-C

Call it with examples/add_two_ints_client.py, or
`zros service call /add_two_ints example_interfaces/srv/AddTwoInts "{a: 2, b: 3}"`.
"""
from __future__ import annotations

import argparse

import zros
from zros.node import Node

from interfaces.example_interfaces.srv import AddTwoInts

from common import parse_args, run


def main(service: str, ros_args: list[str]) -> None:
    with zros.init(args=ros_args), Node('add_two_ints_server') as node:

        def add(request: AddTwoInts.Request, response: AddTwoInts.Response) -> AddTwoInts.Response:
            response.sum = request.a + request.b
            node.get_logger().info(f'Incoming request: a: {request.a} b: {request.b}')
            return response

        node.create_service(AddTwoInts, service, add)
        zros.spin(node)   # requests are answered here, on the executor


if __name__ == '__main__':
    parser = argparse.ArgumentParser(prog='add_two_ints_server', description='Serve AddTwoInts.')
    parser.add_argument('--service', default='add_two_ints', help='service name (default: add_two_ints)')
    args = parse_args(parser)
    run(main, args.service)
