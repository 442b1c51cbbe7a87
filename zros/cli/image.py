"""`zros image save TOPIC out.png [--timeout S]`: write one frame of an image topic as PNG.

Waits for the next sensor_msgs/Image on TOPIC (subscribed best effort, which matches reliable
and best-effort publishers alike), converts it (zros.view.image) and writes it with zros's
own PNG writer. Module-level imports stay light: the CLI imports every verb at start.
"""
from __future__ import annotations

import argparse
import sys

__all__ = ['add_arguments', 'cmd_save']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='image_verb', metavar='<command>')
    p = sub.add_parser('save', help='Save the next frame of an image topic as a PNG file')
    p.add_argument('topic_name', help='a sensor_msgs/msg/Image topic, e.g. /turtlesim/image')
    p.add_argument('output', help='PNG file to write')
    p.add_argument('--timeout', type=float, default=10.0,
                   help='fail if no frame arrives within this many seconds (default 10)')
    p.set_defaults(handler=cmd_save)


def cmd_save(args: argparse.Namespace) -> int:
    import queue
    import time
    from pathlib import Path

    from interfaces.sensor_msgs.msg import Image
    from zros.cli.common import cli_context, cli_node
    from zros.errors import CliError
    from zros.executors import SingleThreadedExecutor
    from zros.qos import qos_profile_sensor_data
    from zros.view.image import UnsupportedEncoding, image_to_array
    from zros.image_io import encode_png
    topic = args.topic_name if args.topic_name.startswith('/') else '/' + args.topic_name
    ctx = cli_context()
    try:
        node = cli_node(ctx)
        inbox: queue.SimpleQueue = queue.SimpleQueue()
        node.create_subscription(Image, topic, inbox.put, qos_profile_sensor_data)
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        deadline = time.monotonic() + args.timeout
        while inbox.empty():
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise CliError(f"no image arrived on '{topic}' within {args.timeout:g} s")
            executor.spin_once(timeout_sec=min(0.25, remaining))
        msg = inbox.get()
        try:
            pixels = image_to_array(msg)
        except UnsupportedEncoding as exc:
            raise CliError(str(exc)) from None
        try:
            Path(args.output).write_bytes(encode_png(pixels))
        except OSError as exc:
            raise CliError(f'cannot write {args.output}: {exc}') from None
        print(f'Saved a {msg.width}x{msg.height} {msg.encoding} frame of {topic} to {args.output}')
        return 0
    finally:
        ctx.shutdown()
        sys.stdout.flush()
