"""`zros lifecycle nodes|get|set|list`: ros2lifecycle's verbs and output formats.

A lifecycle node is one that serves `<node>/get_state` (lifecycle_msgs/srv/GetState).
`set --wait SECONDS` (zros's) first waits for the node to appear: what a launch's
`EmitEvent(event=ChangeState(...))` runs right after starting the node.
"""
from __future__ import annotations

import argparse
import sys
import time

from zros.cli.common import absolute_node_name, cli_context, cli_node, graph_entities
from zros.errors import CliError, ServiceCallError
from zros.graph import EntityKind
from zros.graph_content import is_hidden

__all__ = ['add_arguments', 'lifecycle_node_names']

_GET_STATE_TYPE = 'lifecycle_msgs/srv/GetState'


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='lifecycle_verb', metavar='<command>')
    p = sub.add_parser('nodes', help='Output a list of nodes with lifecycle')
    p.add_argument('-a', '--all', action='store_true', help='Display all nodes even hidden ones')
    p.add_argument('-c', '--count-nodes', action='store_true', help='Only display the number of nodes discovered')
    p.set_defaults(handler=cmd_nodes)
    p = sub.add_parser('get', help='Get lifecycle state for one or more nodes')
    p.add_argument('node_name', nargs='?', help='Name of the node; without it, every lifecycle node')
    p.add_argument('--include-hidden-nodes', action='store_true', help='Consider hidden nodes as well')
    p.set_defaults(handler=cmd_get)
    p = sub.add_parser('set', help='Trigger lifecycle state transition')
    p.add_argument('node_name', help='Name of the node')
    p.add_argument('transition', help='The transition, by label (configure) or id (1)')
    p.add_argument('--include-hidden-nodes', action='store_true', help='Consider hidden nodes as well')
    p.add_argument('--wait', type=_seconds, default=0.0, metavar='SECONDS',
                   help='Wait up to SECONDS for the node and its lifecycle services to appear (zros)')
    p.set_defaults(handler=cmd_set)
    p = sub.add_parser('list', help='Output a list of available transitions')
    p.add_argument('node_name', help='Name of the node')
    p.add_argument('-a', '--all', action='store_true', help='Display all existing transitions')
    p.add_argument('--include-hidden-nodes', action='store_true', help='Consider hidden nodes as well')
    p.set_defaults(handler=cmd_list)


def lifecycle_node_names(entities: list, include_hidden: bool = False) -> list[str]:
    """Fully qualified names of the nodes that serve a lifecycle get_state service."""
    names = {e.node_fqn for e in entities if e.kind == EntityKind.SERVICE and e.type == _GET_STATE_TYPE
             and e.name == e.node_fqn + '/get_state'}
    return sorted(n for n in names if include_hidden or not is_hidden(n))


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"expected a number of seconds >= 0, got '{text}'")
    return value


def _target(ctx, name: str, include_hidden: bool, wait: float = 0.0) -> str:
    """The node's absolute name, once it serves get_state (looked for up to `wait` seconds)."""
    target = absolute_node_name(name)
    deadline = time.monotonic() + wait
    while target not in lifecycle_node_names(graph_entities(ctx), include_hidden=True):
        if time.monotonic() >= deadline:
            raise CliError('Node not found' + (f' (waited {wait:g} s)' if wait else ''))
        time.sleep(0.2)
    return target


def cmd_nodes(args: argparse.Namespace) -> int:
    with cli_context() as ctx:
        names = lifecycle_node_names(graph_entities(ctx), args.all)
    if args.count_nodes:
        print(len(names))
    else:
        for name in names:
            print(name)
    return 0


def cmd_get(args: argparse.Namespace) -> int:
    from zros.lifecycle import LifecycleClient
    with cli_context() as ctx:
        if args.node_name:
            targets = [_target(ctx, args.node_name, args.include_hidden_nodes)]
        else:
            targets = lifecycle_node_names(graph_entities(ctx), args.include_hidden_nodes)
        node = cli_node(ctx)
        failed = False
        for target in targets:
            try:
                state = LifecycleClient(node, target).get_state(timeout_sec=5.0)
            except ServiceCallError as exc:
                if args.node_name:
                    raise CliError(f"Exception while calling service of node '{target}': {exc}") from None
                print(f"Exception while calling service of node '{target}': {exc}", file=sys.stderr)
                failed = True
                continue
            print(('' if args.node_name else f'{target}: ') + f'{state.label} [{state.state_id}]')
    return 1 if failed else 0


def cmd_set(args: argparse.Namespace) -> int:
    from zros.lifecycle import LifecycleClient
    with cli_context() as ctx:
        deadline = time.monotonic() + args.wait
        target = _target(ctx, args.node_name, args.include_hidden_nodes, args.wait)
        client = LifecycleClient(cli_node(ctx), target)
        if args.wait and not client.wait_for_services(timeout_sec=max(0.0, deadline - time.monotonic())):
            raise CliError(f"Node '{target}' does not serve its lifecycle services (waited {args.wait:g} s)")
        try:
            transitions = client.available_transitions(timeout_sec=5.0)
            chosen = next((t for t in transitions if t.label == args.transition), None) or next(
                (t for t in transitions if str(t.transition_id) == args.transition), None)
            if chosen is None:
                raise CliError('Unknown transition requested, available ones are: ' + ', '.join(
                    f'{t.label} [{t.transition_id}]' for t in transitions))
            success = client.change_state(chosen.transition_id)
        except ServiceCallError as exc:
            raise CliError(f"Exception while calling service of node '{args.node_name}': {exc}") from None
    if success:
        print('Transitioning successful')
        return 0
    print('Transitioning failed', file=sys.stderr)
    return 1


def cmd_list(args: argparse.Namespace) -> int:
    from zros.lifecycle import LifecycleClient
    from zros.lifecycle.state_machine import PUBLIC_TRANSITIONS, RESULT_TRANSITIONS
    with cli_context() as ctx:
        target = _target(ctx, args.node_name, args.include_hidden_nodes)
        try:
            transitions = (list(PUBLIC_TRANSITIONS + RESULT_TRANSITIONS) if args.all
                           else LifecycleClient(cli_node(ctx), target).available_transitions(timeout_sec=5.0))
        except ServiceCallError as exc:
            raise CliError(f"Exception while calling service of node '{args.node_name}': {exc}") from None
    for t in transitions:
        print(f'- {t.label} [{t.transition_id}]\n\tStart: {t.start.label}\n\tGoal: {t.goal.label}')
    return 0
