"""`zros view [-d FILE] [--fixed-frame F] [--port P] [--topic T] [--screenshot PNG]`: the scene view in the browser.

RViz's role (3D scene, displays, 2D Pose Estimate / Nav2 Goal tools, teleop) with the topics,
graph, console and image pages beside it (zros.view.scene). Without `-d` every topic a display
can draw is shown as it appears. It prints the page's URL and the image page's, and runs until
Ctrl-C; with `--screenshot` it instead saves one picture of the page, once its displays are
drawn (headless Chromium), and exits. Module-level imports stay light: the CLI imports every verb at start.
"""
from __future__ import annotations

import argparse

__all__ = ['add_arguments', 'cmd_view', 'serve']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('-d', '--display-config', metavar='FILE', default='',
                        help='a .rviz file or a zros view file (saved from the page) to start from')
    parser.add_argument('-f', '--fixed-frame', default='', help='the fixed frame (default: the file\'s, else map, '
                                                                'else odom, else a root of the TF tree)')
    parser.add_argument('--port', type=int, default=None,
                        help='TCP port (default 8080, or the next free one up to 8089; 0 picks any free port)')
    parser.add_argument('--host', default='127.0.0.1',
                        help='address to listen on (default 127.0.0.1: this machine only)')
    parser.add_argument('--topic', default='',
                        help='an image topic to show first (e.g. /turtlesim/image)')
    parser.add_argument('--use-sim-time', action='store_true',
                        help='stamp the tools\' messages with /clock time, as the rest of a simulated robot does')
    parser.add_argument('--screenshot', metavar='PNG', default='',
                        help='save one screenshot of the page (headless Chromium) once its displays are drawn, '
                             'then exit')
    parser.add_argument('--timeout', type=float, default=20.0,
                        help='with --screenshot: seconds to wait for the displays to be drawn (default 20)')
    parser.set_defaults(handler=cmd_view)


def cmd_view(args: argparse.Namespace) -> int:
    return serve(args)


def serve(args: argparse.Namespace, *, page: str = '', plot: list[str] | None = None) -> int:
    """Run the view node (opened on `page`, plotting `plot`) until Ctrl-C; `zros rqt` uses it too."""
    from zros.cli.common import cli_context
    from zros.errors import CliError
    from zros.executors import SingleThreadedExecutor
    from zros.view.scene.app import ViewError
    from zros.view.scene.config import ConfigError
    from zros.parameter import Parameter
    from zros.view.scene.node import ViewNode
    ctx = cli_context()
    try:
        try:
            node = ViewNode('view' if not page else 'rqt', config=getattr(args, 'display_config', ''),
                            fixed_frame=getattr(args, 'fixed_frame', ''), port=args.port, host=args.host,
                            topic=getattr(args, 'topic', ''), page=page, plot=plot or (), context=ctx,
                            parameter_overrides=[Parameter('use_sim_time', value=True)] if getattr(
                                args, 'use_sim_time', False) else None)
        except (ConfigError, ViewError) as exc:
            raise CliError(str(exc) + (' (choose another with --port)' if isinstance(exc, ViewError) else '')) \
                from None
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        if getattr(args, 'screenshot', ''):
            try:
                return _screenshot(node, executor, args.screenshot, args.timeout)
            finally:
                node.destroy_node()
        verb = 'zros rqt' if page else 'zros view'
        print(f'{verb}: serving {node.view.url} (Ctrl-C to stop)', flush=True)
        print(f'{verb}: full-size images at {node.images.page_url()}', flush=True)
        try:
            while ctx.ok():
                executor.spin_once(timeout_sec=0.25)
        except KeyboardInterrupt:
            pass
        finally:
            node.destroy_node()
        return 0
    finally:
        ctx.shutdown()


def _screenshot(node, executor, path: str, timeout: float) -> int:
    """Spin the view while headless Chromium takes its one screenshot (zros.view.headless.one_shot)."""
    import sys
    import threading

    from zros.errors import CliError
    from zros.view.headless import BrowserError, one_shot
    outcome: dict[str, object] = {}

    def shoot() -> None:
        try:
            outcome['drawn'] = one_shot(node.view.url, path, timeout=timeout)
        except (BrowserError, OSError) as exc:
            outcome['error'] = exc
    shooter = threading.Thread(target=shoot, name='zros-view-screenshot', daemon=True)
    shooter.start()
    while shooter.is_alive():
        executor.spin_once(timeout_sec=0.1)
    if 'error' in outcome:
        error = outcome['error']
        reason = error.strerror if isinstance(error, OSError) and error.strerror else str(error)
        raise CliError(f'cannot take the screenshot {path}: {reason}')
    if not outcome.get('drawn'):
        print(f'zros view: not every display was drawn within {timeout:g} s; saved the page as it was',
              file=sys.stderr)
    print(f'zros view: wrote {path}', flush=True)
    return 0
