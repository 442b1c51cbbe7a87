"""`zros tf tree|monitor`: the frame tree and its rates, read from /tf and /tf_static.

`tree` prints the frames as an indented tree (what view_frames draws, in the terminal);
`monitor` prints per frame its parent, rate and the age of its newest transform (tf2_monitor's
role). Both listen for `-t` seconds first.
"""
from __future__ import annotations

import argparse
import json
import time

from zros.cli.common import cli_context, cli_node

__all__ = ['add_arguments']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='tf_verb', metavar='<command>')
    for name, handler, help_text in (('tree', cmd_tree, 'Print the frame tree'),
                                     ('monitor', cmd_monitor, 'Print each frame\'s parent, rate and delay')):
        p = sub.add_parser(name, help=help_text)
        p.add_argument('-t', '--wait-time', type=float, default=2.0, help='seconds to listen first (default 2)')
        p.add_argument('--json', action='store_true', help='Machine-readable output')
        p.set_defaults(handler=handler)


def _listen(seconds: float) -> tuple[dict, int]:
    from zros.tf2_ros import Buffer, TransformListener
    with cli_context() as ctx:
        node = cli_node(ctx)
        buffer = Buffer()
        TransformListener(buffer, node)
        time.sleep(max(0.0, seconds))
        return buffer.frames(), time.time_ns()


def cmd_tree(args: argparse.Namespace) -> int:
    frames, _ = _listen(args.wait_time)
    children: dict[str, list[str]] = {}
    for child, info in frames.items():
        children.setdefault(info['parent'], []).append(child)
    roots = sorted(set(children) - set(frames))
    if args.json:
        def nest(frame: str) -> dict:
            return {c: nest(c) for c in sorted(children.get(frame, []))}
        print(json.dumps({root: nest(root) for root in roots}))
        return 0
    if not frames:
        print('No tf data received: is anything publishing /tf or /tf_static?')
        return 0

    def show(frame: str, prefix: str, last: bool, top: bool) -> None:
        info = frames.get(frame)
        tag = '' if info is None else (' (static)' if info['static'] else f" ({info['rate']:.1f} Hz)")
        print(frame if top else f"{prefix}{'└── ' if last else '├── '}{frame}{tag}")
        kids = sorted(children.get(frame, []))
        for i, kid in enumerate(kids):
            show(kid, '' if top else prefix + ('    ' if last else '│   '), i == len(kids) - 1, False)
    for root in roots:
        show(root, '', True, True)
    return 0


def cmd_monitor(args: argparse.Namespace) -> int:
    frames, now = _listen(args.wait_time)
    rows = [{'frame': child, 'parent': info['parent'], 'static': info['static'],
             'rate_hz': None if info['static'] else round(info['rate'], 3),
             'delay_s': None if info['static'] else round((now - info['newest']) / 1e9, 6)}
            for child, info in sorted(frames.items())]
    if args.json:
        print(json.dumps(rows))
        return 0
    print(f"{'frame':<24} {'parent':<24} {'rate [Hz]':>10} {'delay [s]':>10}")
    for row in rows:
        rate = 'static' if row['static'] else f"{row['rate_hz']:.2f}"
        delay = '-' if row['static'] else f"{row['delay_s']:.3f}"
        print(f"{row['frame']:<24} {row['parent']:<24} {rate:>10} {delay:>10}")
    return 0
