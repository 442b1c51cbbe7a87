"""`zros topic list|info|type|find|echo|pub` with ros2 topic's options and output."""
from __future__ import annotations

import argparse
import json
import sys
import time

from zros.cli.common import cli_context, cli_node, graph_entities, is_hidden, wait_for_graph
from zros.graph import EntityKind, names_and_types

__all__ = ['add_arguments']

_TOPIC_KINDS = (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='topic_verb', metavar='<command>')

    p = sub.add_parser('list', help='Output a list of available topics')
    p.add_argument('-t', '--show-types', action='store_true', help='Additionally show the topic type')
    p.add_argument('-c', '--count-topics', action='store_true', help='Only display the number of topics discovered')
    p.add_argument('-v', '--verbose', action='store_true', help='List full details about each topic')
    p.add_argument('--include-hidden-topics', action='store_true', help='Consider hidden topics as well')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_list)

    p = sub.add_parser('info', help='Print information about a topic')
    p.add_argument('topic_name')
    p.add_argument('-v', '--verbose', action='store_true', help='Print detailed information (nodes, QoS)')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=cmd_info)

    p = sub.add_parser('type', help='Print a topic\'s type')
    p.add_argument('topic_name')
    p.set_defaults(handler=cmd_type)

    p = sub.add_parser('find', help='Output a list of available topics of a given type')
    p.add_argument('topic_type')
    p.add_argument('-c', '--count-topics', action='store_true')
    p.add_argument('--include-hidden-topics', action='store_true')
    p.set_defaults(handler=cmd_find)

    p = sub.add_parser('echo', help='Output messages from a topic')
    p.add_argument('topic_name')
    p.add_argument('message_type', nargs='?', help="Type of the message (e.g. 'std_msgs/msg/String'); "
                   'taken from the graph when omitted')
    p.add_argument('--once', action='store_true', help='Print the first message received and then exit')
    p.add_argument('--field', help='Echo a selected field of a message (e.g. linear.x)')
    p.add_argument('--timeout', type=float, help='Exit with an error if nothing arrives within this many seconds')
    p.add_argument('--no-arr', action='store_true', help="Don't print array fields of messages")
    p.add_argument('--no-str', action='store_true', help="Don't print string fields of messages")
    p.add_argument('--csv', action='store_true', help='Output all recursive fields separated by commas')
    p.add_argument('--json', action='store_true', help='One JSON object per line')
    p.add_argument('--flow-style', action='store_true', help='Print collections in the YAML flow style')
    p.add_argument('-l', '--truncate-length', type=int, default=128, help='Truncate strings and arrays (default 128)')
    p.add_argument('-f', '--full-length', action='store_true', help='Output all elements of arrays and strings')
    p.add_argument('--qos-depth', type=int, default=100, help='Queue depth of the subscription (default 100)')
    p.set_defaults(handler=cmd_echo)

    p = sub.add_parser('pub', help='Publish a message to a topic')
    p.add_argument('topic_name')
    p.add_argument('message_type', help="e.g. 'std_msgs/msg/String'")
    p.add_argument('values', nargs='?', default='{}', help="Values in YAML, e.g. '{data: hi}'")
    p.add_argument('-r', '--rate', type=float, default=1.0, help='Publishing rate in Hz (default 1)')
    p.add_argument('-1', '--once', action='store_true', help='Publish one message and exit')
    p.add_argument('-t', '--times', type=int, default=0, help='Publish this number of times and then exit')
    p.add_argument('-p', '--print', type=int, default=1, help='Print every N-th published message (0: never)')
    p.add_argument('-w', '--wait-matching-subscriptions', type=int, default=None,
                   help='Wait for this many subscriptions before publishing (default 1 with --once/--times, else 0)')
    p.add_argument('--max-wait-time-secs', type=float, default=5.0,
                   help='How long -w waits before publishing anyway, with a warning (default 5)')
    p.add_argument('--keep-alive', type=float, default=0.1, help='Keep publishing node alive for N seconds after the last message')
    p.set_defaults(handler=cmd_pub)


def _visible_topics(entities, include_hidden: bool):
    return [(name, types) for name, types in names_and_types(entities, _TOPIC_KINDS)
            if include_hidden or not is_hidden(name)]


def cmd_list(args: argparse.Namespace) -> int:
    with cli_context() as ctx:
        entities = graph_entities(ctx)
    topics = _visible_topics(entities, args.include_hidden_topics)
    if args.json:
        print(json.dumps([{'name': n, 'types': t,
                           'publisher_count': sum(1 for e in entities if e.kind == EntityKind.PUBLISHER and e.name == n),
                           'subscription_count': sum(1 for e in entities if e.kind == EntityKind.SUBSCRIPTION and e.name == n)}
                          for n, t in topics]))
    elif args.count_topics:
        print(len(topics))
    elif args.verbose:
        for title, kind in (('Published topics', EntityKind.PUBLISHER), ('Subscribed topics', EntityKind.SUBSCRIPTION)):
            print(f'{title}:')
            for name, types in names_and_types(entities, (kind,)):
                if args.include_hidden_topics or not is_hidden(name):
                    count = sum(1 for e in entities if e.kind == kind and e.name == name)
                    noun = 'publisher' if kind == EntityKind.PUBLISHER else 'subscriber'
                    print(f" * {name} [{', '.join(types)}] {count} {noun}{'s' if count != 1 else ''}")
            print()
    else:
        for name, types in topics:
            print(f"{name} [{', '.join(types)}]" if args.show_types else name)
    return 0


def _types_of(entities, topic: str) -> list[str]:
    return sorted({e.type for e in entities if e.kind in _TOPIC_KINDS and e.name == topic})


def _absolute(name: str) -> str:
    from zros.names import expand_topic_name
    return expand_topic_name(name, 'zros', '/')


def cmd_info(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.qos import QoSProfile
    topic = _absolute(args.topic_name)
    with cli_context() as ctx:
        entities = graph_entities(ctx)
    types = _types_of(entities, topic)
    if not types:
        raise CliError(f"Unknown topic '{topic}'")
    pubs = [e for e in entities if e.kind == EntityKind.PUBLISHER and e.name == topic]
    subs = [e for e in entities if e.kind == EntityKind.SUBSCRIPTION and e.name == topic]
    if args.json:
        def describe(e):
            return {'node': e.node_fqn, 'type': e.type, 'type_hash': e.type_hash, 'qos': e.qos}
        print(json.dumps({'name': topic, 'types': types, 'publishers': [describe(e) for e in pubs],
                          'subscriptions': [describe(e) for e in subs]}))
        return 0
    print(f"Type: {', '.join(types)}")
    for title, group, kind in (('Publisher', pubs, 'PUBLISHER'), ('Subscription', subs, 'SUBSCRIPTION')):
        if args.verbose:
            print()
        print(f'{title} count: {len(group)}')
        if args.verbose:
            for e in group:
                qos = QoSProfile.from_token(e.qos)
                print()
                print(f'Node name: {e.node_name}')
                print(f'Node namespace: {e.namespace}')
                print(f'Topic type: {e.type}')
                print(f'Topic type hash: {e.type_hash}')
                print(f'Endpoint type: {kind}')
                print(f'GID: {e.zid}.{e.node_id}.{e.entity_id}')
                print('QoS profile:')
                print(f'  Reliability: {qos.reliability.name}')
                print(f'  History (Depth): {qos.history.name} ({qos.depth})')
                print(f'  Durability: {qos.durability.name}')
    return 0


def cmd_type(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    topic = _absolute(args.topic_name)
    with cli_context() as ctx:
        types = _types_of(graph_entities(ctx), topic)
    if not types:
        raise CliError(f"Unknown topic '{topic}'")
    for t in types:
        print(t)
    return 0


def cmd_find(args: argparse.Namespace) -> int:
    with cli_context() as ctx:
        topics = [n for n, types in _visible_topics(graph_entities(ctx), args.include_hidden_topics)
                  if args.topic_type in types]
    if args.count_topics:
        print(len(topics))
    else:
        for name in topics:
            print(name)
    return 0


def _echo_qos(entities, topic: str, depth: int):
    """ros2 topic echo's rule: reliable / transient local only if every publisher offers it."""
    from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    offers = [QoSProfile.from_token(e.qos) for e in entities if e.kind == EntityKind.PUBLISHER and e.name == topic]
    reliable = bool(offers) and all(q.reliability == ReliabilityPolicy.RELIABLE for q in offers)
    transient = bool(offers) and all(q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in offers)
    return QoSProfile(depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE)


def cmd_echo(args: argparse.Namespace) -> int:
    import queue

    from zros.errors import CliError
    from zros.convert import get_field, message_to_csv, message_to_ordereddict, message_to_yaml
    from zros.typesupport import get_message
    topic = _absolute(args.topic_name)
    with cli_context() as ctx:
        if args.message_type:
            msg_type = get_message(args.message_type)
            entities = graph_entities(ctx)
        else:
            entities = wait_for_graph(ctx, lambda es: bool(_types_of(es, topic)), 2.0)
            types = _types_of(entities or [], topic)
            if not types:
                raise CliError(f"Could not determine the type for the passed topic '{topic}': "
                               'it has no publisher yet; pass the type as an argument')
            if len(types) > 1:
                raise CliError(f"Topic '{topic}' has more than one type ({', '.join(types)}); pass one as an argument")
            msg_type = get_message(types[0])
        if args.field:
            get_field(msg_type(), args.field)  # fail fast on a bad field path
        truncate = None if args.full_length else args.truncate_length
        inbox: queue.SimpleQueue = queue.SimpleQueue()
        node = cli_node(ctx)
        node.create_subscription(msg_type, topic, inbox.put, _echo_qos(entities, topic, args.qos_depth))
        from zros.executors import SingleThreadedExecutor
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        deadline = None if args.timeout is None else time.monotonic() + args.timeout
        out = sys.stdout
        while True:
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                raise CliError(f"timed out after {args.timeout} s waiting for a message on '{topic}'")
            executor.spin_once(timeout_sec=0.25 if remaining is None else min(0.25, remaining))
            printed = False
            while True:
                try:
                    msg = inbox.get_nowait()
                except queue.Empty:
                    break
                value = get_field(msg, args.field) if args.field else msg
                if args.csv:
                    out.write((message_to_csv(value, truncate_length=truncate, no_arr=args.no_arr, no_str=args.no_str)
                               if hasattr(value, '_FIELDS') else str(value)) + '\n')
                elif args.json:
                    plain = (message_to_ordereddict(value, truncate_length=truncate, no_arr=args.no_arr,
                                                    no_str=args.no_str) if hasattr(value, '_FIELDS') else _plain(value))
                    out.write(json.dumps(plain) + '\n')
                else:
                    if hasattr(value, '_FIELDS'):
                        text = message_to_yaml(value, truncate_length=truncate, no_arr=args.no_arr,
                                               no_str=args.no_str, flow_style=args.flow_style)
                    else:
                        import yaml
                        text = yaml.safe_dump(_plain(value), default_flow_style=args.flow_style)
                        text = text[:-4] if text.endswith('\n...\n') else text
                    out.write(text + '---\n')
                printed = True
                if args.once:
                    out.flush()
                    return 0
            if printed:
                out.flush()


def _plain(value):
    import numpy as np
    return value.tolist() if isinstance(value, np.ndarray) else value


def cmd_pub(args: argparse.Namespace) -> int:
    from zros.convert import message_from_yaml
    from zros.typesupport import get_message
    topic = _absolute(args.topic_name)
    msg_type = get_message(args.message_type)
    msg = message_from_yaml(msg_type, args.values)
    times = 1 if args.once else args.times
    wait_for = args.wait_matching_subscriptions
    if wait_for is None:
        wait_for = 1 if times else 0
    if args.rate <= 0:
        from zros.errors import CliError
        raise CliError('--rate must be > 0')
    with cli_context() as ctx:
        node = cli_node(ctx)
        publisher = node.create_publisher(msg_type, topic, 10)
        if wait_for > 0 and not publisher.wait_for_subscribers(wait_for, args.max_wait_time_secs):
            print(f'Waiting for at least {wait_for} matching subscription(s) timed out after '
                  f'{args.max_wait_time_secs} s; publishing anyway', file=sys.stderr)
        print('publisher: beginning loop')
        count = 0
        period = 1.0 / args.rate
        next_time = time.monotonic()
        while True:
            count += 1
            publisher.publish(msg)
            if args.print and count % args.print == 0:
                print(f'publishing #{count}: {msg!r}\n', flush=True)
            if times and count >= times:
                break
            next_time += period
            time.sleep(max(0.0, next_time - time.monotonic()))
        time.sleep(max(0.0, args.keep_alive))
    return 0
