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
from typing import Any, Sequence

from zros.node import Node
from zros.view.scene.app import DEFAULT_PORT, SceneView, ViewError
from zros.view.scene.config import ConfigError, DisplayConfig, load_config

__all__ = ['ViewNode', 'run_view_node', 'parse_rviz_args', 'parse_rqt_args', 'expand_plot_fields', 'rqt_main', 'RQT_PAGES']

#: rqt's executables (`zros run PKG PKG`) and the page each opens; rqt_gui is the whole UI.
RQT_PAGES = {'rqt_gui': 'Topics', 'rqt_graph': 'Graph', 'rqt_plot': 'Plot', 'rqt_console': 'Console',
             'rqt_reconfigure': 'Parameters', 'rqt_topic': 'Topics', 'rqt_service_caller': 'Services'}


class ViewNode(Node):
    """Serves the scene view (and the image page) for its context's graph.

    Raises:
        ConfigError: the config file cannot be read.
        ViewError: the port cannot be bound.
    """

    def __init__(self, name: str = 'view', *, config: str = '', fixed_frame: str = '', port: int | None = None,
                 host: str | None = None, topic: str = '', page: str = '', plot: Sequence[str] = (),
                 **kwargs: Any) -> None:
        super().__init__(name, **kwargs)
        config = self.declare_parameter('config', config).value
        fixed_frame = self.declare_parameter('fixed_frame', fixed_frame).value
        port = int(self.declare_parameter('port', DEFAULT_PORT if port is None else port).value)
        host = self.declare_parameter('host', host or '127.0.0.1').value
        topic = self.declare_parameter('topic', topic).value
        view_config = load_config(config) if config else None
        if fixed_frame and view_config is not None:
            view_config.fixed_frame = fixed_frame.lstrip('/')
        from zros.view.server import ViewServer
        self.images = ViewServer(self, host=host, port=0, topic=_absolute(topic)).start()
        try:
            self.view = SceneView(self, config=view_config, host=host, port=port,
                                  port_tries=10 if port == DEFAULT_PORT else 1,
                                  image_page_url=self.images.page_url(_absolute(topic)), first_page=page, plot=plot)
        except Exception:
            self.images.close()
            raise
        if fixed_frame and view_config is None:       # every topic as it appears, in this frame
            self.view.set_fixed_frame(fixed_frame, user=True)
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


def parse_rqt_args(name: str, argv: list[str]) -> argparse.Namespace:
    """An rqt tool's arguments: rqt_plot's field paths (`/turtle1/pose/x`, `/turtle1/pose/x:y`)."""
    parser = argparse.ArgumentParser(prog=name, description=f'{name}: rqt in the browser (the zros view, '
                                     f'{RQT_PAGES[name]} page)')
    if name == 'rqt_plot':
        parser.add_argument('fields', nargs='*', help='topic field paths to plot, e.g. /turtle1/pose/x /turtle1/pose/y '
                            'or /turtle1/pose/x:y')
    parser.add_argument('--port', type=int, default=None, help='TCP port (default 8080, or the next free one)')
    args, _unknown = parser.parse_known_args(argv)
    args.display_config = args.fixed_frame = ''
    args.fields = expand_plot_fields(getattr(args, 'fields', []))
    return args


def expand_plot_fields(fields: Sequence[str]) -> list[str]:
    """rqt_plot's `/topic/a:b` shorthand for `/topic/a /topic/b`."""
    out = []
    for field in fields:
        head, _, tail = field.rpartition('/')
        if ':' in tail:
            out.extend(f'{head}/{one}' for one in tail.split(':') if one)
        else:
            out.append(field)
    return out


def run_view_node(name: str, argv: list[str] | None) -> int:
    """`main()` of the rviz2, zros_view and rqt_* nodes: run a ViewNode until Ctrl-C or shutdown."""
    import zros
    from zros.executors import ExternalShutdownException
    from zros.utilities import remove_ros_args
    own = remove_ros_args(list(argv or sys.argv))[1:]
    args = parse_rqt_args(name, own) if name in RQT_PAGES else parse_rviz_args(own)
    try:
        with zros.init(args=argv):
            try:
                node = ViewNode(name, config=args.display_config, fixed_frame=args.fixed_frame, port=args.port,
                                page=RQT_PAGES.get(name, ''), plot=getattr(args, 'fields', ()))
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


def rqt_main(args: list[str] | None = None) -> int:
    """`main()` of the rqt_* nodes: the page is chosen by the executable's name (argv[0])."""
    from pathlib import Path
    argv = list(args if args is not None else sys.argv)
    name = Path(argv[0]).stem if argv else ''
    return run_view_node(name if name in RQT_PAGES else 'rqt_gui', argv)


def _absolute(topic: str | None) -> str | None:
    if not topic:
        return None
    return topic if topic.startswith('/') else '/' + topic
