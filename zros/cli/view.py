"""`zros view [--port P] [--topic T]`: show sensor_msgs/Image topics live in the browser.

Serves zros.view's page on localhost (standard library HTTP server, no CDN) and prints its
URL; runs until Ctrl-C. Module-level imports stay light: the CLI imports every verb at start.
"""
from __future__ import annotations

import argparse

__all__ = ['add_arguments', 'cmd_view']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--port', type=int, default=None,
                        help='TCP port (default 8080, or the next free one up to 8089; 0 picks any free port)')
    parser.add_argument('--host', default='127.0.0.1',
                        help='address to listen on (default 127.0.0.1: this machine only)')
    parser.add_argument('--topic', default=None,
                        help='image topic to show first (default /turtlesim/image if present, else the first one)')
    parser.set_defaults(handler=cmd_view)


def cmd_view(args: argparse.Namespace) -> int:
    from zros.cli.common import cli_context, cli_node
    from zros.errors import CliError
    from zros.executors import SingleThreadedExecutor
    from zros.view.server import DEFAULT_PORT, ViewServer
    ctx = cli_context()
    try:
        node = cli_node(ctx)
        explicit = args.port is not None
        try:
            server = ViewServer(node, host=args.host, port=args.port if explicit else DEFAULT_PORT,
                                topic=_absolute(args.topic), port_tries=1 if explicit else 10)
        except OSError as exc:
            raise CliError(f'{exc} (choose another with --port)') from None
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        with server:
            print(f'zros view: serving {server.page_url()} (Ctrl-C to stop)', flush=True)
            try:
                while ctx.ok():
                    executor.spin_once(timeout_sec=0.25)
            except KeyboardInterrupt:
                pass
        return 0
    finally:
        ctx.shutdown()


def _absolute(topic: str | None) -> str | None:
    if not topic:
        return None
    return topic if topic.startswith('/') else '/' + topic
