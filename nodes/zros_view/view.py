"""view: the zros web view as a node (`zros run zros_view view`), for launch files.

Serves zros.view's page, which shows sensor_msgs/Image topics live in the browser, and logs
its URL. Parameters (read at start):
  port (int, default 8080: the next free port up to 8089 is taken if it is busy; 0 = any),
  host (string, default 127.0.0.1: this machine only),
  topic (string, default '': /turtlesim/image if present, else the first image topic).
`zros view` is the same thing as a CLI verb.
"""
from __future__ import annotations

import sys

import zros
from zros.executors import ExternalShutdownException
from zros.node import Node
from zros.view.server import DEFAULT_PORT, ViewServer

__all__ = ['ImageView', 'main']


class ImageView(Node):

    def __init__(self) -> None:
        super().__init__('view')
        port = self.declare_parameter('port', DEFAULT_PORT).value
        host = self.declare_parameter('host', '127.0.0.1').value
        topic = self.declare_parameter('topic', '').value
        if topic and not topic.startswith('/'):
            topic = '/' + topic
        self.server = ViewServer(self, host=host, port=int(port), topic=topic or None,
                                 port_tries=10 if int(port) == DEFAULT_PORT else 1)
        self.server.start()
        self.get_logger().info(f'Serving the image view on {self.server.page_url()}')

    def destroy_node(self) -> None:
        self.server.close()
        super().destroy_node()


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            try:
                node = ImageView()
            except OSError as exc:
                print(f'view: {exc}', file=sys.stderr)
                return 1
            try:
                zros.spin(node)
            finally:
                node.destroy_node()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
