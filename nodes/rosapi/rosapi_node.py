"""rosapi_node: serves /rosapi/topics, /rosapi/nodes, /rosapi/get_param ... (zros.bridges.rosapi).

    zros run rosapi rosapi_node
"""
from __future__ import annotations

import sys

import zros
from zros.bridges.rosapi import Rosapi
from zros.executors import ExternalShutdownException, spin_nodes
from zros.node import Node

__all__ = ['main']


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = Node('rosapi')
            Rosapi(node)
            spin_nodes(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
