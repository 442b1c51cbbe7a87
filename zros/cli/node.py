"""`zros node list|info`."""
from __future__ import annotations

import argparse
import json

from zros.cli.common import absolute_node_name, cli_context, graph_entities
from zros.graph import EntityKind
from zros.graph_content import is_hidden

__all__ = ['add_arguments']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='node_verb', metavar='<command>')
    p = sub.add_parser('list', help='Output a list of available nodes')
    p.add_argument('-a', '--all', action='store_true', help='Display all nodes even hidden ones')
    p.add_argument('-c', '--count-nodes', action='store_true', help='Only display the number of nodes discovered')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_list)
    p = sub.add_parser('info', help='Output information about a node')
    p.add_argument('node_name', help='Fully qualified node name, e.g. /talker')
    p.add_argument('--include-hidden', action='store_true', help='Display hidden topics, services and actions')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_info)


def _node_names(entities, include_hidden: bool) -> list[str]:
    names = {e.node_fqn for e in entities if e.kind == EntityKind.NODE}
    return sorted(n for n in names if include_hidden or not is_hidden(n))


def cmd_list(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
        names = _node_names(graph_entities(ctx), args.all)
    if args.json:
        print(json.dumps(names))
    elif args.count_nodes:
        print(len(names))
    else:
        for name in names:
            print(name)
    return 0


_SECTIONS = (
    ('Subscribers', EntityKind.SUBSCRIPTION), ('Publishers', EntityKind.PUBLISHER),
    ('Service Servers', EntityKind.SERVICE), ('Service Clients', EntityKind.CLIENT),
    ('Action Servers', EntityKind.ACTION_SERVER), ('Action Clients', EntityKind.ACTION_CLIENT),
)


def cmd_info(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    target = absolute_node_name(args.node_name)
    with cli_context(graph_only=True) as ctx:
        entities = graph_entities(ctx)
    mine = [e for e in entities if e.node_fqn == target]
    if not any(e.kind == EntityKind.NODE for e in mine):
        raise CliError(f"Unable to find node '{args.node_name}'")
    count = len({e.node_key for e in mine if e.kind == EntityKind.NODE})
    sections = {}
    for title, kind in _SECTIONS:
        table: dict[str, set[str]] = {}
        for e in mine:
            if e.kind == kind and (args.include_hidden or not is_hidden(e.name)):
                table.setdefault(e.name, set()).add(e.type)
        sections[title] = {name: sorted(types) for name, types in sorted(table.items())}
    if args.json:
        print(json.dumps({'node': target, **sections}))
        return 0
    if count > 1:
        print(f'There are {count} nodes in the graph with the exact name "{target}". '
              'You are seeing information about only one of them.')
    print(target)
    for title, table in sections.items():
        print(f'  {title}:')
        for name, types in table.items():
            print(f"    {name}: {', '.join(types)}")
        if not table:
            print()  # ros2 node info prints an empty line under an empty section
    return 0
