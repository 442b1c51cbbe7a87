"""`zros graph`: the node/topic graph (what rqt_graph draws) as Graphviz DOT, or rendered SVG.

Nodes are ellipses, topics boxes; an edge goes from each publishing node to its topic and from
the topic to each subscribing node. As in rqt_graph's default view, hidden names (a part that
starts with '_', such as the CLI's own nodes and action internals) and the debug topics
(/rosout, /parameter_events) are left out unless asked for.
"""
from __future__ import annotations

import argparse
import json

from zros.graph_content import graph_content

__all__ = ['add_arguments', 'to_dot']

def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('--dot', metavar='FILE', help="Write the DOT text to FILE ('-': stdout, the default)")
    parser.add_argument('--svg', metavar='FILE', help="Render the graph to FILE as SVG (needs Graphviz's dot)")
    parser.add_argument('--include-hidden', action='store_true', help='Show hidden nodes and topics too')
    parser.add_argument('--include-debug', action='store_true', help='Show /rosout and /parameter_events too')
    parser.add_argument('--json', action='store_true', help='Print nodes, topics and edges as JSON instead')
    parser.set_defaults(handler=cmd_graph)


def _quote(text: str) -> str:
    return '"' + text.replace('\\', '\\\\').replace('"', '\\"') + '"'


def to_dot(content: dict) -> str:
    lines = ['digraph zros_graph {', '  rankdir=LR;', '  node [fontname="sans-serif", fontsize=11];']
    for name in content['nodes']:
        lines.append(f'  {_quote("n:" + name)} [label={_quote(name)}, shape=ellipse];')
    for name, types in content['topics'].items():
        label = name + '\\n' + ', '.join(types)
        lines.append(f'  {_quote("t:" + name)} [label="{label.replace(chr(34), "")}", shape=box];')
    for src, dst in content['edges']:
        lines.append(f'  {_quote(src)} -> {_quote(dst)};')
    lines.append('}')
    return '\n'.join(lines) + '\n'


def cmd_graph(args: argparse.Namespace) -> int:
    import shutil
    import subprocess

    from zros.cli.common import cli_context, graph_entities
    from zros.errors import CliError
    dot_binary = shutil.which('dot') if args.svg else None
    if args.svg and dot_binary is None:
        raise CliError("cannot render SVG: Graphviz's 'dot' program is not installed "
                       '(e.g. apt install graphviz); --dot FILE writes the DOT text instead')
    with cli_context(graph_only=True) as ctx:
        content = graph_content(graph_entities(ctx), include_hidden=args.include_hidden,
                                include_debug=args.include_debug)
    if args.json:
        print(json.dumps({**content, 'edges': [list(e) for e in content['edges']]}))
        return 0
    text = to_dot(content)
    if args.dot and args.dot != '-':
        try:
            with open(args.dot, 'w') as handle:
                handle.write(text)
        except OSError as exc:
            raise CliError(f"cannot write '{args.dot}': {exc.strerror}") from None
    elif not args.svg or args.dot == '-':
        print(text, end='')
    if args.svg:
        result = subprocess.run([dot_binary, '-Tsvg', '-o', args.svg], input=text.encode(), capture_output=True)
        if result.returncode != 0:
            reason = result.stderr.decode(errors='replace').strip().splitlines()
            raise CliError(f"dot failed to render '{args.svg}': {reason[0] if reason else 'exit ' + str(result.returncode)}")
    return 0
