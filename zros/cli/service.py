"""`zros service list|type|find|call` with ros2 service's options and output."""
from __future__ import annotations

import argparse
import json
import time

from zros.cli.common import absolute_name, cli_context, cli_node, graph_entities
from zros.graph import EntityKind, names_and_types
from zros.graph_content import is_hidden

__all__ = ['add_arguments']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='service_verb', metavar='<command>')
    p = sub.add_parser('list', help='Output a list of available services')
    p.add_argument('-t', '--show-types', action='store_true', help='Additionally show the service type')
    p.add_argument('-c', '--count-services', action='store_true', help='Only display the number of services discovered')
    p.add_argument('--include-hidden-services', action='store_true', help='Consider hidden services as well')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_list)
    p = sub.add_parser('type', help="Output a service's type")
    p.add_argument('service_name')
    p.set_defaults(handler=cmd_type)
    p = sub.add_parser('find', help='Output a list of available services of a given type')
    p.add_argument('service_type')
    p.add_argument('-c', '--count-services', action='store_true')
    p.add_argument('--include-hidden-services', action='store_true')
    p.set_defaults(handler=cmd_find)
    p = sub.add_parser('call', help='Call a service')
    p.add_argument('service_name', help="e.g. '/add_two_ints'")
    p.add_argument('service_type', help="e.g. 'example_interfaces/srv/AddTwoInts'")
    p.add_argument('values', nargs='?', default='{}', help="Request values in YAML, e.g. '{a: 1, b: 2}'")
    p.add_argument('-r', '--rate', type=float, help='Repeat the call at this rate in Hz (default: call once)')
    p.add_argument('--timeout', type=float, default=10.0,
                   help='Seconds to wait for the service to appear and for each answer (default 10)')
    p.add_argument('--json', action='store_true',
                   help='Print only each response, as one JSON object per line (instead of ros2\'s text)')
    p.set_defaults(handler=cmd_call)


def _services(entities, include_hidden: bool):
    return [(n, t) for n, t in names_and_types(entities, (EntityKind.SERVICE,))
            if include_hidden or not is_hidden(n)]


def cmd_list(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
        services = _services(graph_entities(ctx), args.include_hidden_services)
    if args.json:
        print(json.dumps([{'name': n, 'types': t} for n, t in services]))
    elif args.count_services:
        print(len(services))
    else:
        for name, types in services:
            print(f"{name} [{', '.join(types)}]" if args.show_types else name)
    return 0


def cmd_type(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    name = absolute_name(args.service_name, 'service name')
    with cli_context(graph_only=True) as ctx:
        types = dict(_services(graph_entities(ctx), True)).get(name)
    if not types:
        raise CliError(f"Unknown service '{name}'")
    for t in types:
        print(t)
    return 0


def cmd_find(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
        names = [n for n, t in _services(graph_entities(ctx), args.include_hidden_services) if args.service_type in t]
    if args.count_services:
        print(len(names))
    else:
        for name in names:
            print(name)
    return 0


def cmd_call(args: argparse.Namespace) -> int:
    """ros2 service call's output: the request and the response in their repr form, e.g.
    `response:` / `example_interfaces.srv.AddTwoInts_Response(sum=3)`, each followed by a blank line."""
    from zros.convert import message_from_yaml, message_to_ordereddict
    from zros.errors import CliError
    from zros.typesupport import get_service
    name = absolute_name(args.service_name, 'service name')
    srv_type = get_service(args.service_type)
    request = message_from_yaml(srv_type.Request, args.values)
    if args.rate is not None and args.rate <= 0:
        raise CliError('--rate must be > 0')
    say = (lambda text: None) if args.json else (lambda text: print(text, flush=True))
    with cli_context() as ctx:
        node = cli_node(ctx)
        client = node.create_client(srv_type, name)
        if not client.service_is_ready():
            say('waiting for service to become available...')
            if not client.wait_for_service(args.timeout):
                raise CliError(f"service '{name}' did not appear within {args.timeout} s")
        offered = {e.type for e in graph_entities(ctx) if e.kind == EntityKind.SERVICE and e.name == name}
        if offered and srv_type._TYPE not in offered:
            raise CliError(f"service '{name}' is of type {', '.join(sorted(offered))}, not {srv_type._TYPE}")
        period = None if not args.rate else 1.0 / args.rate
        while True:
            started = time.monotonic()
            say(f'requester: making request: {request!r}\n')
            response = client.call(request, timeout_sec=args.timeout)
            if response is None:
                raise CliError(f"service '{name}' did not answer within {args.timeout:g} s")
            if args.json:
                print(json.dumps(message_to_ordereddict(response)), flush=True)
            else:
                say(f'response:\n{response!r}\n')
            if period is None:
                return 0
            time.sleep(max(0.0, period - (time.monotonic() - started)))
