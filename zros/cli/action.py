"""`zros action list|info|type|find|send_goal` with ros2 action's options and output."""
from __future__ import annotations

import argparse
import json

from zros.cli.common import absolute_name, cli_context, cli_node, graph_entities
from zros.graph import EntityKind, names_and_types
from zros.graph_content import is_hidden

__all__ = ['add_arguments']

_STATUS = {0: 'UNKNOWN', 1: 'ACCEPTED', 2: 'EXECUTING', 3: 'CANCELING', 4: 'SUCCEEDED', 5: 'CANCELED', 6: 'ABORTED'}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='action_verb', metavar='<command>')
    p = sub.add_parser('list', help='Output a list of action names')
    p.add_argument('-t', '--show-types', action='store_true', help='Additionally show the action type')
    p.add_argument('-c', '--count-actions', action='store_true', help='Only display the number of actions discovered')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_list)
    p = sub.add_parser('info', help='Print information about an action')
    p.add_argument('action_name')
    p.add_argument('-t', '--show-types', action='store_true', help='Additionally show the action type')
    p.add_argument('-c', '--count', action='store_true', help='Only display the number of action clients and servers')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_info)
    p = sub.add_parser('type', help="Print an action's type")
    p.add_argument('action_name')
    p.set_defaults(handler=cmd_type)
    p = sub.add_parser('find', help='Find actions of a given type')
    p.add_argument('action_type')
    p.add_argument('-c', '--count-actions', action='store_true')
    p.set_defaults(handler=cmd_find)
    p = sub.add_parser('send_goal', help='Send an action goal')
    p.add_argument('action_name', help="e.g. '/fibonacci'")
    p.add_argument('action_type', help="e.g. 'action_tutorials_interfaces/action/Fibonacci'")
    p.add_argument('goal', nargs='?', default='{}', help="Goal values in YAML, e.g. '{order: 5}'")
    p.add_argument('-f', '--feedback', action='store_true', help='Echo feedback messages for the goal')
    p.add_argument('--timeout', type=float, default=10.0,
                   help='Seconds to wait for the action server to appear (default 10); the goal itself may run as long as it needs')
    p.add_argument('--json', action='store_true',
                   help='Print JSON lines instead of ros2\'s text: {"goal_id"}, {"feedback"} (with -f), '
                        '{"status", "result"}')
    p.set_defaults(handler=cmd_send_goal)


_KINDS = (EntityKind.ACTION_SERVER, EntityKind.ACTION_CLIENT)


def _actions(entities):
    return [(n, t) for n, t in names_and_types(entities, _KINDS) if not is_hidden(n)]


def cmd_list(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
        actions = _actions(graph_entities(ctx))
    if args.json:
        print(json.dumps([{'name': n, 'types': t} for n, t in actions]))
    elif args.count_actions:
        print(len(actions))
    else:
        for name, types in actions:
            print(f"{name} [{', '.join(types)}]" if args.show_types else name)
    return 0


def cmd_info(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    name = absolute_name(args.action_name, 'action name')
    with cli_context(graph_only=True) as ctx:
        entities = [e for e in graph_entities(ctx) if e.kind in _KINDS and e.name == name]
    if not entities:
        raise CliError(f"Unknown action '{name}'")
    clients = sorted((e.node_fqn, e.type) for e in entities if e.kind == EntityKind.ACTION_CLIENT)
    servers = sorted((e.node_fqn, e.type) for e in entities if e.kind == EntityKind.ACTION_SERVER)
    if args.json:
        print(json.dumps({'name': name, 'clients': [{'node': n, 'type': t} for n, t in clients],
                          'servers': [{'node': n, 'type': t} for n, t in servers]}))
        return 0
    print(f'Action: {name}')
    for title, group in (('Action clients', clients), ('Action servers', servers)):
        print(f'{title}: {len(group)}')
        if not args.count:
            for node, type_name in group:
                print(f'    {node} [{type_name}]' if args.show_types else f'    {node}')
    return 0


def cmd_type(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    name = absolute_name(args.action_name, 'action name')
    with cli_context(graph_only=True) as ctx:
        types = dict(_actions(graph_entities(ctx))).get(name)
    if not types:
        raise CliError(f"Unknown action '{name}'")
    for t in types:
        print(t)
    return 0


def cmd_find(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
        names = [n for n, t in _actions(graph_entities(ctx)) if args.action_type in t]
    if args.count_actions:
        print(len(names))
    else:
        for name in names:
            print(name)
    return 0


def _ros2_block(title: str, msg, indent: str = '    ') -> str:
    """ros2 action's layout: the title line, then the message's YAML with only its first line
    indented (ros2 prints `'Result:\\n    {}'.format(message_to_yaml(...))`), then a blank line."""
    from zros.convert import message_to_yaml
    return f'{title}\n{indent}{message_to_yaml(msg)}'


# How long send_goal waits for the server to confirm a cancel after Ctrl-C.
_CANCEL_WAIT_S = 2.5


def cmd_send_goal(args: argparse.Namespace) -> int:
    from zros.action import ActionClient
    from zros.convert import message_from_yaml, message_to_ordereddict
    from zros.errors import CliError
    from zros.executors import SingleThreadedExecutor
    from zros.signals import exit_on_signals
    from zros.typesupport import get_action
    name = absolute_name(args.action_name, 'action name')
    action_type = get_action(args.action_type)
    goal = message_from_yaml(action_type.Goal, args.goal)

    def say(text: str) -> None:
        if not args.json:
            print(text, flush=True)

    def emit(record: dict) -> None:
        if args.json:
            print(json.dumps(record), flush=True)

    with cli_context() as ctx:
        node = cli_node(ctx)
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)

        def on_feedback(message) -> None:
            say(_ros2_block('Feedback:', message.feedback))
            emit({'feedback': message_to_ordereddict(message.feedback)})

        client = ActionClient(node, action_type, name)
        say('Waiting for an action server to become available...')
        if not client.server_is_ready() and not client.wait_for_server(args.timeout):
            raise CliError(f"action server '{name}' did not appear within {args.timeout} s")
        say(_ros2_block('Sending goal:', goal, indent='     '))
        sent = client.send_goal_async(goal, feedback_callback=on_feedback if args.feedback else None)
        executor.spin_until_future_complete(sent, timeout_sec=args.timeout)
        if not sent.done():
            raise CliError(f"action server '{name}' did not answer the goal within {args.timeout} s")
        handle = sent.result()
        if not handle.accepted:
            say('Goal was rejected.')
            emit({'accepted': False})
            return 1
        try:   # from here on, Ctrl-C cancels the goal first, as ros2's does
            exit_on_signals(grace_s=_CANCEL_WAIT_S + 0.5)
            result = handle.get_result_async()
            goal_id = bytes(handle.goal_id.uuid).hex()
            say(f'Goal accepted with ID: {goal_id}\n')
            emit({'accepted': True, 'goal_id': goal_id})
            while not result.done():
                executor.spin_once(timeout_sec=0.1)
        except KeyboardInterrupt:
            say('Canceling goal...')
            cancel = handle.cancel_goal_async()
            executor.spin_until_future_complete(cancel, timeout_sec=_CANCEL_WAIT_S)
            response = cancel.result() if cancel.done() else None
            if response is None or not response.goals_canceling:
                say('Failed to cancel goal')
                return 130
            say('Goal canceled.')
            emit({'status': 'CANCELED'})
            return 130
        response = result.result()
        status = _STATUS.get(response.status, str(response.status))
        say(_ros2_block('Result:', response.result))
        say(f'Goal finished with status: {status}')
        emit({'status': status, 'result': message_to_ordereddict(response.result)})
        return 0 if response.status == 4 else 1
