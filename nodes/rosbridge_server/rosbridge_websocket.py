"""rosbridge_websocket: the rosbridge v2 protocol on a WebSocket, port 9090 by default.

    zros run rosbridge_server rosbridge_websocket --ros-args -p port:=9090 -p address:=127.0.0.1

The protocol is zros.bridges.rosbridge, the transport zros.bridges.websocket; this node only
reads the parameters, starts both and spins. `port` 0 takes any free port (the log line says which,
as upstream's does; the `actual_port` parameter too).
"""
from __future__ import annotations

import sys

import zros
from zros.bridges.rosbridge import Rosbridge
from zros.bridges.websocket import DEFAULT_SEND_BUFFER_LIMIT, WebSocketServer
from zros.executors import ExternalShutdownException, spin_nodes
from zros.node import Node

__all__ = ['main']


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            node = Node('rosbridge_websocket')
            port = node.declare_parameter('port', 9090).value
            address = node.declare_parameter('address', '').value
            max_message_size = node.declare_parameter('max_message_size', 10_000_000).value
            send_buffer_limit = node.declare_parameter('send_buffer_limit', DEFAULT_SEND_BUFFER_LIMIT).value
            if not 0 <= port <= 65535:
                print(f'rosbridge_websocket: port {port} is not a TCP port (0-65535; 0 takes a free one)',
                      file=sys.stderr)
                return 1
            server = WebSocketServer(Rosbridge(node, max_message_size=max_message_size), address=address,
                                     port=port, send_buffer_limit=send_buffer_limit)
            try:
                actual_port = server.start()
            except OSError as exc:
                print(f"rosbridge_websocket: cannot listen on {address or '*'}:{port}: {exc.strerror or exc}",
                      file=sys.stderr)
                return 1
            node.declare_parameter('actual_port', actual_port)
            node.get_logger().info(f'Rosbridge WebSocket server started on port {actual_port}')
            try:
                spin_nodes(node)
            finally:
                server.stop()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
