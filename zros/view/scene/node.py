"""The view as a node: `zros view`, `zros run rviz2 rviz2 -d file.rviz` and `zros run zros_view view`
all run this, so a launch file that starts RViz starts the same page.

Parameters (read at start): `config` (a .rviz file or a zros view file; '' = show every topic
as it appears), `fixed_frame` ('' = the file's, else map/odom/a root frame), `port` (8080: the
next free one up to 8089 is taken if it is busy; 0 = any), `host` (127.0.0.1: this machine
only), `topic` (an image topic to show first, as the image view did). Besides the scene it
serves the full-size image page (zros.view.ViewServer) on a free port, linked from the
Images tab.
"""
from __future__ import annotations

import argparse
import sys
from typing import Any

from zros.node import Node
from zros.view.scene.app import DEFAULT_PORT, SceneView, ViewError
from zros.view.scene.config import ConfigError, DisplayConfig, ViewConfig, load_config

__all__ = ['ViewNode', 'run_view_node', 'parse_rviz_args']


class ViewNode(Node):
    """Serves the scene view (and the image page) for its context's graph.

    Raises:
        ConfigError: the config file cannot be read.
        ViewError: the port cannot be bound.
    """

    def __init__(self, name: str = 'view', *, config: str = '', fixed_frame: str = '', port: int | None = None,
                 host: str | None = None, topic: str = '', **kwargs: Any) -> None:
        super().__init__(name, **kwargs)
        config = self.declare_parameter('config', config).value
        fixed_frame = self.declare_parameter('fixed_frame', fixed_frame).value
        port = int(self.declare_parameter('port', DEFAULT_PORT if port is None else port).value)
        host = self.declare_parameter('host', host or '127.0.0.1').value
        topic = self.declare_parameter('topic', topic).value
        view_config = load_config(config) if config else None
        if fixed_frame:
            view_config = view_config or ViewConfig(displays=[DisplayConfig('TF', 'TF')])
            view_config.fixed_frame = fixed_frame.lstrip('/')
        from zros.view.server import ViewServer
        self.images = ViewServer(self, host=host, port=0, topic=_absolute(topic)).start()
        try:
            self.view = SceneView(self, config=view_config, host=host, port=port,
                                  port_tries=10 if port == DEFAULT_PORT else 1,
                                  image_page_url=self.images.page_url(_absolute(topic)))
        except Exception:
            self.images.close()
            raise
        if topic and not any(d.topic == _absolute(topic) for d in self.view.displays):
            self.view.add_display(DisplayConfig('Image', 'Image', _absolute(topic), 'sensor_msgs/msg/Image'))
        if view_config is not None and view_config.unknown:
            self.get_logger().warn('Not shown (display classes zros does not draw): ' + ', '.join(view_config.unknown))

    def destroy_node(self) -> None:
        """Stop serving, then undeclare the node (idempotent: shutdown and the caller may both call it)."""
        view, self.view = getattr(self, 'view', None), None
        if view is not None:
            view.close()
        images, self.images = getattr(self, 'images', None), None
        if images is not None:
            images.close()
        super().destroy_node()


def parse_rviz_args(argv: list[str]) -> argparse.Namespace:
    """rviz2's own options (`-d FILE`, `-f FRAME`), ignoring the ones that mean nothing here."""
    parser = argparse.ArgumentParser(prog='rviz2', description='The zros scene view (RViz in the browser)')
    parser.add_argument('-d', '--display-config', default='', help='a .rviz file (or a zros view file)')
    parser.add_argument('-f', '--fixed-frame', default='', help='the fixed frame')
    parser.add_argument('-s', '--splash-screen', default='', help=argparse.SUPPRESS)
    parser.add_argument('--port', type=int, default=None, help='TCP port (default 8080, or the next free one)')
    args, _unknown = parser.parse_known_args(argv)
    return args


def run_view_node(name: str, argv: list[str] | None) -> int:
    """`main()` of the rviz2 and zros_view nodes: run a ViewNode until Ctrl-C or shutdown."""
    import zros
    from zros.executors import ExternalShutdownException
    from zros.utilities import remove_ros_args
    args = parse_rviz_args(remove_ros_args(list(argv or sys.argv))[1:])
    try:
        with zros.init(args=argv):
            try:
                node = ViewNode(name, config=args.display_config, fixed_frame=args.fixed_frame, port=args.port)
            except (ConfigError, ViewError, OSError) as exc:
                print(f'{name}: {exc}', file=sys.stderr)
                return 1
            node.get_logger().info(f'Serving the view on {node.view.url}')
            try:
                zros.spin(node)
            finally:
                node.destroy_node()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


def _absolute(topic: str | None) -> str | None:
    if not topic:
        return None
    return topic if topic.startswith('/') else '/' + topic
