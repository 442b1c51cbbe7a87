"""`zros topic list|info|type|find|echo|pub` with ros2 topic's options and output."""
from __future__ import annotations

import argparse
import array
import json
import sys
import time
from typing import TYPE_CHECKING

from zros.cli.common import absolute_name, cli_context, cli_node, graph_entities, wait_for_graph
from zros.graph import EntityKind, names_and_types
from zros.graph_content import is_hidden

if TYPE_CHECKING:
    from zros.duration import Duration

__all__ = ['add_arguments', 'add_qos_arguments', 'qos_from_args']

_TOPIC_KINDS = (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION)
# ros2 topic echo's default cut for the text formats (YAML, CSV) that people read.
_TEXT_TRUNCATE_LENGTH = 128


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
    p.add_argument('--timeout', type=float,
                   help='Exit with an error if no (further) message arrives within this many seconds')
    p.add_argument('--filter', dest='filter_expr', metavar='EXPR',
                   help="Only print messages for which this Python expression of 'm' is true "
                        "(e.g. \"m.data == 'hello'\"); 'm' is the --field value when given")
    p.add_argument('-i', '--include-message-info', action='store_true',
                   help='Print the message info (timestamps, sequence numbers) with each message')
    p.add_argument('--no-arr', action='store_true', help="Don't print array fields of messages")
    p.add_argument('--no-str', action='store_true', help="Don't print string fields of messages")
    p.add_argument('--csv', action='store_true', help='Output all recursive fields separated by commas')
    p.add_argument('--json', action='store_true', help='One JSON object per line')
    p.add_argument('--raw', action='store_true', help='Print the raw payload bytes (MessagePack) instead of decoding')
    p.add_argument('--flow-style', action='store_true', help='Print collections in the YAML flow style')
    p.add_argument('-l', '--truncate-length', type=_non_negative_int, default=None,
                   help=f'Truncate strings and arrays after N elements (default {_TEXT_TRUNCATE_LENGTH}; '
                        '--json output is complete unless this is given)')
    p.add_argument('-f', '--full-length', action='store_true', help='Output all elements of arrays and strings')
    p.add_argument('--no-lost-messages', action='store_true', help="Don't report lost messages (accepted; zros "
                   'reports them only with -i)')
    p.add_argument('-n', '--node-name', help='Name of the echoing node (default: a hidden one)')
    add_qos_arguments(p, 'sensor_data', depth_default=100, adapted=True)
    p.set_defaults(handler=cmd_echo)

    p = sub.add_parser('pub', help='Publish a message to a topic')
    p.add_argument('topic_name')
    p.add_argument('message_type', help="e.g. 'std_msgs/msg/String'")
    p.add_argument('values', nargs='?', default='{}', help="Values in YAML, e.g. '{data: hi}'")
    p.add_argument('-r', '--rate', type=float, default=1.0, help='Publishing rate in Hz (default 1)')
    p.add_argument('-1', '--once', action='store_true', help='Publish one message and exit')
    p.add_argument('-t', '--times', type=_non_negative_int, default=0,
                   help='Publish this number of times and then exit')
    p.add_argument('-p', '--print', type=_non_negative_int, default=1,
                   help='Print every N-th published message (0: never)')
    p.add_argument('--stdin', action='store_true',
                   help='Read the values from standard input instead: YAML documents separated by "---" '
                        'lines, or one flow mapping / JSON object per line; each is published once, as it '
                        'arrives, and the command ends at end of input')
    p.add_argument('-w', '--wait-matching-subscriptions', type=_non_negative_int, default=None,
                   help='Wait for this many subscriptions before publishing (default 1 with --once/--times, else 0)')
    p.add_argument('--max-wait-time-secs', type=float, default=5.0,
                   help='How long -w waits before publishing anyway, with a warning (default 5)')
    p.add_argument('--keep-alive', type=float, default=0.1,
                   help='Keep the publishing node alive for N seconds after the last message (default 0.1)')
    p.add_argument('-n', '--node-name', help='Name of the publishing node (default: a hidden one)')
    add_qos_arguments(p, 'default', depth_default=None, adapted=False)
    p.set_defaults(handler=cmd_pub)

    p = sub.add_parser('hz', help='Print the average publishing rate to screen')
    p.add_argument('topic_name', nargs='+', help="Names of the topics to listen to (e.g. '/chatter')")
    p.add_argument('-w', '--window', dest='window_size', type=_positive_int, default=10000, metavar='WINDOW',
                   help='Window size, in # of messages, for calculating rate (default 10000)')
    p.add_argument('--filter', dest='filter_expr', metavar='EXPR',
                   help="Only measure messages matching this Python expression of 'm' (decodes every message)")
    p.add_argument('--wall-time', action='store_true',
                   help='Accepted for ros2 compatibility: zros always measures receive times on the wall clock')
    p.add_argument('--timeout', type=float,
                   help='Exit with an error if no message arrives within this many seconds')
    p.set_defaults(handler=cmd_hz)

    p = sub.add_parser('bw', help='Display bandwidth used by topic')
    p.add_argument('topic_name')
    p.add_argument('-w', '--window', type=_positive_int, default=100, metavar='WINDOW',
                   help='Window size, in # of messages, for calculating the rate (default 100)')
    p.add_argument('--timeout', type=float,
                   help='Exit with an error if no message arrives within this many seconds')
    p.set_defaults(handler=cmd_bw)

    p = sub.add_parser('delay', help='Display delay of topic from timestamp in header')
    p.add_argument('topic_name')
    p.add_argument('-w', '--window', type=_positive_int, default=10000, metavar='WINDOW',
                   help='Window size, in # of messages, for calculating the delay (default 10000)')
    p.add_argument('--timeout', type=float,
                   help='Exit with an error if no message arrives within this many seconds')
    p.set_defaults(handler=cmd_delay)


_QOS_PROFILES = ('default', 'sensor_data', 'services_default', 'parameters', 'parameter_events',
                 'system_default', 'action_status_default', 'best_available')


def _non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got '{text}'")
    return value


def _positive_int(text: str) -> int:
    value = _non_negative_int(text)
    if value == 0:
        raise argparse.ArgumentTypeError('expected a positive integer, got 0')
    return value


def add_qos_arguments(parser: argparse.ArgumentParser, default_profile: str, *, depth_default: int | None,
                      adapted: bool) -> None:
    """ros2's QoS flags. With `adapted`, reliability and durability follow the publishers unless given."""
    what = 'subscribe' if adapted else 'publish'
    parser.add_argument('--qos-profile', choices=_QOS_PROFILES, default=None,
                        help=f'Quality of service preset profile to {what} with (default: {default_profile})')
    depth_text = f' (default {depth_default})' if depth_default else ''
    parser.add_argument('--qos-depth', type=_positive_int, default=depth_default, metavar='N',
                        help=f'Queue size setting to {what} with (overrides the profile\'s depth){depth_text}')
    parser.add_argument('--qos-history', choices=('system_default', 'keep_last', 'keep_all'),
                        help=f'History of samples setting to {what} with (overrides the profile)')
    adapt = '; by default the publishers\' offer is adapted to, as ros2 does' if adapted else ''
    parser.add_argument('--qos-reliability', choices=('system_default', 'reliable', 'best_effort', 'best_available'),
                        help=f'Reliability setting to {what} with (overrides the profile{adapt})')
    parser.add_argument('--qos-durability', choices=('system_default', 'volatile', 'transient_local',
                                                     'best_available'),
                        help=f'Durability setting to {what} with (overrides the profile{adapt})')
    parser.add_argument('--qos-liveliness', choices=('system_default', 'automatic', 'manual_by_topic'),
                        help='Liveliness setting (accepted; zros liveliness is always automatic)')
    parser.set_defaults(_qos_default_profile=default_profile)


def qos_from_args(args: argparse.Namespace, publishers_qos: list | None = None):
    """The profile the QoS flags ask for. `publishers_qos` (a list of offered profiles) turns on
    ros2 echo's adaptation: reliable / transient local only if every publisher offers it, unless
    the flags say otherwise; `best_available` means the same adaptation."""
    from dataclasses import replace

    from zros.qos import DurabilityPolicy, HistoryPolicy, QoSPresetProfiles, ReliabilityPolicy
    profile = QoSPresetProfiles.get_from_short_key(args.qos_profile or args._qos_default_profile)
    changes = {}
    if args.qos_history:
        changes['history'] = HistoryPolicy[args.qos_history.upper()]
    if args.qos_depth:
        changes['depth'] = args.qos_depth
    reliability, durability = args.qos_reliability, args.qos_durability
    adapt = publishers_qos is not None and args.qos_profile is None
    if reliability == 'best_available' or (reliability is None and adapt):
        offers = publishers_qos or []
        reliable = bool(offers) and all(q.reliability == ReliabilityPolicy.RELIABLE for q in offers)
        changes['reliability'] = ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT
    elif reliability:
        changes['reliability'] = ReliabilityPolicy[reliability.upper()]
    if durability == 'best_available' or (durability is None and adapt):
        offers = publishers_qos or []
        transient = bool(offers) and all(q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in offers)
        changes['durability'] = DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE
    elif durability:
        changes['durability'] = DurabilityPolicy[durability.upper()]
    return replace(profile, **changes)


def _visible_topics(entities, include_hidden: bool):
    return [(name, types) for name, types in names_and_types(entities, _TOPIC_KINDS)
            if include_hidden or not is_hidden(name)]


def cmd_list(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
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


def cmd_info(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    from zros.qos import QoSProfile
    from zros.graph import fetch_subscription_stats
    topic = absolute_name(args.topic_name)
    with cli_context(graph_only=not (args.verbose or args.json)) as ctx:
        entities = graph_entities(ctx)
        stats = fetch_subscription_stats(ctx.session, ctx.domain_id) if args.verbose or args.json else {}
    types = _types_of(entities, topic)
    if not types:
        raise CliError(f"Unknown topic '{topic}'")
    pubs = [e for e in entities if e.kind == EntityKind.PUBLISHER and e.name == topic]
    subs = [e for e in entities if e.kind == EntityKind.SUBSCRIPTION and e.name == topic]
    hashes = _TypeHashes()
    if args.json:
        def describe(e):
            counters = stats.get((e.zid, e.node_id, e.entity_id))
            extra = {} if counters is None else dict(zip(('received', 'dropped', 'lost', 'rejected'), counters))
            return {'node': e.node_fqn, 'type': e.type, 'type_hash': e.type_hash,
                    'type_hash_rihs01': hashes.rihs01(e.type, e.type_hash), 'qos': e.qos, **extra}
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
                print(f'Topic type hash: {hashes.text(e.type, e.type_hash)}')
                print(f'Endpoint type: {kind}')
                print(f'GID: {e.zid}.{e.node_id}.{e.entity_id}')
                print('QoS profile:')
                print(f'  Reliability: {qos.reliability.name}')
                print(f'  History (Depth): {qos.history.name} ({qos.depth})')
                print(f'  Durability: {qos.durability.name}')
                print(f'  Lifespan: {_qos_duration(qos.lifespan)}')
                print(f'  Deadline: {_qos_duration(qos.deadline)}')
                print(f'  Liveliness: {qos.liveliness.name}')
                print(f'  Liveliness lease duration: {_qos_duration(qos.liveliness_lease_duration)}')
                counters = stats.get((e.zid, e.node_id, e.entity_id))
                if counters is not None:
                    received, dropped, lost, rejected = counters
                    print('Delivery:')
                    print(f'  Received: {received}')
                    print(f'  Dropped (queue depth full): {dropped}')
                    print(f'  Lost (gaps in publisher sequence): {lost}')
                    print(f'  Rejected (wrong type or corrupt): {rejected}')
    return 0


def _qos_duration(duration: 'Duration') -> str:
    """As ros2 topic info -v prints a QoS duration: unset (0) is Infinite."""
    return f'{duration.nanoseconds} nanoseconds' if duration.nanoseconds else 'Infinite'


class _TypeHashes:
    """The type hash `topic info -v` prints (docs/cli.md): ROS 2's `RIHS01_<64 hex>`, computed from
    this machine's definition of the type, when the endpoint announces that same definition (its
    zros hash matches ours); otherwise `ZROS_<16 hex>`, the zros type hash it announced
    (docs/protocol.md, *The type hash*), which says its definition is not the one installed here."""

    def __init__(self) -> None:
        self._codec = None
        self._known: dict[tuple[str, str], str | None] = {}

    def rihs01(self, type_name: str, zros_hash: str) -> str | None:
        key = (type_name, zros_hash)
        if key not in self._known:
            self._known[key] = self._compute(type_name, zros_hash)
        return self._known[key]

    def _compute(self, type_name: str, zros_hash: str) -> str | None:
        from zros.errors import ZrosError
        from zros.typesupport import get_message
        try:
            if get_message(type_name)._HASH != zros_hash:
                return None
            if self._codec is None:
                from zros.bag.cdr import CdrCodec
                self._codec = CdrCodec()
            return self._codec.rihs01(type_name)
        except ZrosError:
            return None

    def text(self, type_name: str, zros_hash: str) -> str:
        return self.rihs01(type_name, zros_hash) or f'ZROS_{zros_hash}'


def cmd_type(args: argparse.Namespace) -> int:
    from zros.errors import CliError
    topic = absolute_name(args.topic_name)
    with cli_context(graph_only=True) as ctx:
        types = _types_of(graph_entities(ctx), topic)
    if not types:
        raise CliError(f"Unknown topic '{topic}'")
    for t in types:
        print(t)
    return 0


def cmd_find(args: argparse.Namespace) -> int:
    with cli_context(graph_only=True) as ctx:
        topics = [n for n, types in _visible_topics(graph_entities(ctx), args.include_hidden_topics)
                  if args.topic_type in types]
    if args.count_topics:
        print(len(topics))
    else:
        for name in topics:
            print(name)
    return 0


def _offered_qos(entities, topic: str) -> list:
    from zros.qos import QoSProfile
    return [QoSProfile.from_token(e.qos) for e in entities if e.kind == EntityKind.PUBLISHER and e.name == topic]


def _compile_filter(expr: str | None):
    """`--filter EXPR` as a function of the message `m`; a syntax error is a one-line CliError."""
    from zros.errors import CliError
    if not expr:
        return None
    try:
        code = compile(expr, '<filter>', 'eval')
    except SyntaxError as exc:
        raise CliError(f"invalid --filter expression '{expr}': {exc.msg}") from None

    def accept(m) -> bool:
        try:
            return bool(eval(code, {'__builtins__': __builtins__}, {'m': m}))
        except Exception as exc:  # noqa: BLE001 - the user's expression; report it on one line
            raise CliError(f"--filter expression '{expr}' failed: {type(exc).__name__}: {exc}") from None
    return accept


def _node_for(ctx, name: str | None):
    """The verb's node: hidden by default (ros2cli's `_ros2cli_...`), or `-n NAME`."""
    if not name:
        return cli_node(ctx)
    from zros.node import Node
    return Node(name, context=ctx, enable_rosout=False, use_global_arguments=False)


def _resolve_type(ctx, topic: str, given: str | None, wait: float = 2.0):
    """(message class, graph entities): the given type, or the topic's only type in the graph."""
    from zros.errors import CliError
    from zros.typesupport import get_message
    if given:
        msg_type = get_message(given)
        entities = graph_entities(ctx)
        types = _types_of(entities, topic)
        if types and msg_type._TYPE not in types:
            raise CliError(f"topic '{topic}' has type {', '.join(types)}, not {msg_type._TYPE}")
        return msg_type, entities
    entities = wait_for_graph(ctx, lambda es: bool(_types_of(es, topic)), wait)
    types = _types_of(entities or [], topic)
    if not types:
        raise CliError(f"Could not determine the type for the passed topic '{topic}': "
                       'it has no publisher yet; pass the type as an argument')
    if len(types) > 1:
        raise CliError(f"Topic '{topic}' has more than one type ({', '.join(types)}); pass one as an argument")
    return get_message(types[0]), entities


def _truncate_length(args: argparse.Namespace) -> int | None:
    """Where echo cuts arrays and strings (None: nowhere). JSON is read by programs, which need
    every element (a '...' inside a number array is not data), so it is complete unless -l is
    given; YAML and CSV keep ros2's default cut."""
    if args.full_length:
        return None
    if args.truncate_length is not None:
        return args.truncate_length
    return None if args.json else _TEXT_TRUNCATE_LENGTH


class _EchoPrinter:
    """Formats one received message the way `ros2 topic echo` does (YAML, CSV, JSON, raw)."""

    def __init__(self, args: argparse.Namespace, out) -> None:
        self.args = args
        self.out = out
        self.truncate = _truncate_length(args)

    def write(self, value, info: dict | None) -> None:
        args, out = self.args, self.out
        is_msg = hasattr(value, '_FIELDS')
        if args.raw:
            if info is not None:
                out.write('---Got new message, message info:---\n' + repr(info) + '\n---Message data:---\n')
            out.write(repr(value) + '\n---\n')
        elif args.csv:
            from zros.convert import message_to_csv
            text = (message_to_csv(value, truncate_length=self.truncate, no_arr=args.no_arr, no_str=args.no_str)
                    if is_msg else str(_plain(value)))
            if info is not None:
                text = ','.join(str(v) for v in info.values()) + ',' + text
            out.write(text + '\n')
        elif args.json:
            from zros.convert import message_to_ordereddict
            plain = (message_to_ordereddict(value, truncate_length=self.truncate, no_arr=args.no_arr,
                                            no_str=args.no_str) if is_msg else _plain(value))
            if info is not None:
                plain = {'message': plain, 'info': info}
            out.write(json.dumps(plain) + '\n')
        else:
            import yaml
            if info is not None:
                out.write(yaml.safe_dump(info, default_flow_style=False) + '---\n')
            if is_msg:
                from zros.convert import message_to_yaml
                text = message_to_yaml(value, truncate_length=self.truncate, no_arr=args.no_arr,
                                       no_str=args.no_str, flow_style=args.flow_style)
            else:
                text = yaml.safe_dump(_plain(value), default_flow_style=args.flow_style, allow_unicode=True)
                text = text[:-4] if text.endswith('\n...\n') else text
            out.write(text + '---\n')


def cmd_echo(args: argparse.Namespace) -> int:
    import queue

    from zros.convert import get_field
    from zros.errors import CliError
    topic = absolute_name(args.topic_name)
    accept = _compile_filter(args.filter_expr)
    if args.timeout is not None and args.timeout <= 0:
        raise CliError('--timeout must be > 0')
    with cli_context() as ctx:
        msg_type, entities = _resolve_type(ctx, topic, args.message_type)
        if args.field:
            get_field(msg_type(), args.field)  # fail fast on a bad field path
        qos = qos_from_args(args, _offered_qos(entities, topic))
        inbox: queue.SimpleQueue = queue.SimpleQueue()
        node = _node_for(ctx, args.node_name)
        node.create_subscription(msg_type, topic, lambda msg, info: inbox.put((msg, info)), qos,
                                 raw=args.raw)
        from zros.executors import SingleThreadedExecutor
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        printer = _EchoPrinter(args, sys.stdout)
        deadline = None if args.timeout is None else time.monotonic() + args.timeout
        while True:
            remaining = None if deadline is None else deadline - time.monotonic()
            if remaining is not None and remaining <= 0:
                raise CliError(f"timed out after {args.timeout} s waiting for a message on '{topic}'")
            executor.spin_once(timeout_sec=0.25 if remaining is None else min(0.25, remaining))
            printed = False
            while True:
                try:
                    msg, info = inbox.get_nowait()
                except queue.Empty:
                    break
                value = get_field(msg, args.field) if args.field and not args.raw else msg
                if accept is not None and not accept(value):
                    continue
                printer.write(value, info if args.include_message_info else None)
                printed = True
                if args.once:
                    sys.stdout.flush()
                    return 0
            if printed:
                sys.stdout.flush()
                if deadline is not None:
                    deadline = time.monotonic() + args.timeout


def _plain(value):
    if type(value).__module__ == 'numpy' or isinstance(value, array.array):
        return value.tolist()
    if isinstance(value, bytes):  # a `byte` field: rclpy's bytes of length 1, shown as its number
        return value[0]
    if isinstance(value, list):
        return [_msg_dict(v) if hasattr(v, '_FIELDS') else _plain(v) for v in value]
    return value


def _msg_dict(msg):
    from zros.convert import message_to_ordereddict
    return message_to_ordereddict(msg)


# -- pub ----------------------------------------------------------------------------------------
def _stdin_documents(stream):
    """YAML documents from `stream` as they complete: a `---` line ends one; so does a line that is
    a whole flow mapping / JSON object on its own (what `zros topic echo --json` prints)."""
    import yaml
    buffer: list[str] = []
    for line in stream:
        stripped = line.strip()
        if stripped in ('---', '...'):
            if ''.join(buffer).strip():
                yield ''.join(buffer)
            buffer = []
            continue
        if not buffer and stripped.startswith('{'):
            try:
                if isinstance(yaml.safe_load(stripped), dict):
                    yield stripped
                    continue
            except yaml.YAMLError:
                pass
        buffer.append(line)
    if ''.join(buffer).strip():
        yield ''.join(buffer)


def _wait_for_subscriptions(publisher, count: int, max_wait: float) -> None:
    """ros2 topic pub's wait: say once a second what it waits for (`Waiting for at least 1
    matching subscription(s)...`); after `max_wait` seconds publish anyway, with a warning."""
    deadline = time.monotonic() + max_wait
    if publisher.wait_for_subscribers(count, min(0.3, max_wait)):  # the graph's first read
        return
    while True:
        print(f'Waiting for at least {count} matching subscription(s)...', flush=True)
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            print(f'Waiting for at least {count} matching subscription(s) timed out after {max_wait:g} s; '
                  'publishing anyway', file=sys.stderr)
            return
        if publisher.wait_for_subscribers(count, min(1.0, remaining)):
            return


def cmd_pub(args: argparse.Namespace) -> int:
    from zros.convert import message_from_yaml
    from zros.errors import CliError
    from zros.typesupport import get_message
    topic = absolute_name(args.topic_name)
    msg_type = get_message(args.message_type)
    msg = None if args.stdin else message_from_yaml(msg_type, args.values)
    times = 1 if args.once else args.times
    wait_for = args.wait_matching_subscriptions
    if wait_for is None:
        wait_for = 1 if (times or args.stdin) else 0
    if args.rate <= 0:
        raise CliError(f'--rate must be > 0, got {args.rate:g}')
    qos = qos_from_args(args)
    with cli_context() as ctx:
        entities = graph_entities(ctx, timeout=0.5)
        types = _types_of(entities, topic)
        if types and msg_type._TYPE not in types:
            raise CliError(f"topic '{topic}' has type {', '.join(types)}, not {msg_type._TYPE}")
        node = _node_for(ctx, args.node_name)
        publisher = node.create_publisher(msg_type, topic, qos)
        if wait_for > 0:
            _wait_for_subscriptions(publisher, wait_for, args.max_wait_time_secs)
        print('publisher: beginning loop', flush=True)
        count = 0
        if args.stdin:
            for text in _stdin_documents(sys.stdin):
                msg = message_from_yaml(msg_type, text)
                count += 1
                publisher.publish(msg)
                if args.print and count % args.print == 0:
                    print(f'publishing #{count}: {msg!r}\n', flush=True)
                if times and count >= times:
                    break
        else:
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


# -- hz / bw / delay -------------------------------------------------------------------------------
class _Monitor:
    """What hz, bw and delay share: wait for the topic's type (as ros2 does, printing a warning
    when it is not published yet), subscribe to raw payloads, and report once a second.

    Receive times are taken on Zenoh's thread as each sample arrives (`received_timestamp`), so
    a busy executor does not distort the figures; the subscription queue is deep enough that
    the executor never has to drop at 1 kHz.
    """

    def __init__(self, args: argparse.Namespace) -> None:
        self.args = args
        names = args.topic_name if isinstance(args.topic_name, list) else [args.topic_name]
        self.topics = list(dict.fromkeys(absolute_name(name) for name in names))
        self.topic = self.topics[0]

    def wait_for_type(self, ctx, topic: str):
        from zros.errors import CliError
        from zros.typesupport import get_message
        deadline = None if self.args.timeout is None else time.monotonic() + self.args.timeout
        warned = False
        while True:
            entities = graph_entities(ctx)
            types = sorted({e.type for e in entities if e.kind == EntityKind.PUBLISHER and e.name == topic})
            if len(types) > 1:
                raise CliError(f"Topic '{topic}' has more than one type ({', '.join(types)})")
            if types:
                return get_message(types[0]), entities
            if not warned:
                print(f'WARNING: topic [{topic}] does not appear to be published yet', flush=True)
                warned = True
            if deadline is not None and time.monotonic() >= deadline:
                raise CliError(f"timed out after {self.args.timeout} s: topic '{topic}' is not published")
            time.sleep(0.2)

    def run(self, callback_for, report, *, raw: bool = True, check=None) -> int:
        """Subscribe to each topic with `callback_for(topic)` and call `report()` every second
        until Ctrl-C (or --timeout with no message). `report()` returns whether any message has
        arrived yet; `check(msg_type)` may refuse a type."""
        from zros.errors import CliError
        from zros.executors import SingleThreadedExecutor
        from zros.qos import QoSProfile, ReliabilityPolicy
        with cli_context() as ctx:
            node = cli_node(ctx)
            for topic in self.topics:
                msg_type, entities = self.wait_for_type(ctx, topic)
                if check is not None:
                    check(msg_type)
                offered = _offered_qos(entities, topic)
                reliable = bool(offered) and all(q.reliability == ReliabilityPolicy.RELIABLE for q in offered)
                qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE if reliable
                                 else ReliabilityPolicy.BEST_EFFORT)
                node.create_subscription(msg_type, topic, callback_for(topic), qos, raw=raw)
                if len(self.topics) > 1:
                    print(f'Subscribed to [{topic}]', flush=True)
            executor = SingleThreadedExecutor(context=ctx)
            executor.add_node(node)
            started = time.monotonic()
            next_report = started + 1.0
            while True:
                executor.spin_once(timeout_sec=max(0.0, next_report - time.monotonic()))
                now = time.monotonic()
                if now >= next_report:
                    next_report += 1.0
                    if next_report < now:
                        next_report = now + 1.0
                    if report():
                        started = None
                    elif (started is not None and self.args.timeout is not None
                          and now - started >= self.args.timeout):
                        raise CliError(f"timed out after {self.args.timeout} s waiting for a message on "
                                       f"'{', '.join(self.topics)}'")


def _stats(values) -> tuple[float, float, float, float]:
    n = len(values)
    mean = sum(values) / n
    return mean, min(values), max(values), (sum((x - mean) ** 2 for x in values) / n) ** 0.5


class _Rate:
    """One topic's receive-time gaps over the last `window` messages (ros2 topic hz's figures)."""

    def __init__(self, window: int) -> None:
        from collections import deque
        self.deltas: deque = deque(maxlen=window)
        self.last: int | None = None
        self.new = False

    def add(self, now: int) -> None:
        if self.last is not None and now >= self.last:
            self.deltas.append(now - self.last)
            self.new = True
        self.last = now

    def take(self) -> tuple[float, float, float, float, int] | None:
        """(rate [Hz], min, max, std dev [s], window) if messages came since the last call."""
        if not self.new or not self.deltas:
            return None
        self.new = False
        mean, low, high, std = _stats(self.deltas)
        return (1e9 / mean if mean > 0 else 0.0), low * 1e-9, high * 1e-9, std * 1e-9, len(self.deltas)


def _ascii_table(header: list[str], rows: list[list[str]]) -> str:
    """ros2 topic hz's table for several topics: centred titles, a `=` rule, left-aligned cells."""
    widths = [max([len(h)] + [len(row[i]) for row in rows]) for i, h in enumerate(header)]
    lines = ['   '.join(h.center(w) for h, w in zip(header, widths)), '=' * (sum(widths) + 3 * (len(header) - 1))]
    lines += ['   '.join(cell.ljust(w) for cell, w in zip(row, widths)) for row in rows]
    return '\n'.join(lines) + '\n'


def cmd_hz(args: argparse.Namespace) -> int:
    monitor = _Monitor(args)
    accept = _compile_filter(args.filter_expr)
    rates = {topic: _Rate(args.window_size) for topic in monitor.topics}

    def callback_for(topic: str):
        rate = rates[topic]

        def on_message(msg, info) -> None:
            if accept is None or accept(msg):
                rate.add(info['received_timestamp'])
        return on_message

    def report() -> bool:
        figures = {topic: rate.take() for topic, rate in rates.items()}
        if len(rates) == 1:
            (figure,) = figures.values()
            if figure is not None:
                hz, low, high, std, window = figure
                print(f'average rate: {hz:.3f}\n\tmin: {low:.3f}s max: {high:.3f}s std dev: {std:.5f}s '
                      f'window: {window}', flush=True)
        else:
            rows = [[topic, f'{hz:.3f}', f'{low:.3f}', f'{high:.3f}', f'{std:.5f}', str(window)]
                    for topic, figure in figures.items() if figure is not None
                    for hz, low, high, std, window in [figure]]
            if rows:
                print(_ascii_table(['topic', 'rate', 'min_delta', 'max_delta', 'std_dev', 'window'], rows),
                      flush=True)
        return any(rate.last is not None for rate in rates.values())
    return monitor.run(callback_for, report, raw=accept is None)


def _bw_units(value: float, per_second: float) -> str:
    """ros2 topic bw's units, chosen by the rate for every figure of a report: `512 B`,
    `1.50 KB`, `2.00 MB` (decimal kilo and mega)."""
    if per_second < 1000:
        return f'{value:.0f} B'
    if per_second < 1_000_000:
        return f'{value / 1000:.2f} KB'
    return f'{value / 1000 / 1000:.2f} MB'


def cmd_bw(args: argparse.Namespace) -> int:
    from collections import deque
    monitor = _Monitor(args)
    samples: deque = deque(maxlen=args.window)  # (receive time ns, size)

    def on_message(payload, info) -> None:
        samples.append((info['received_timestamp'], len(payload)))

    def report() -> bool:
        if len(samples) < 2:
            return bool(samples)
        window = list(samples)
        elapsed = (time.time_ns() - window[0][0]) / 1e9
        sizes = [size for _, size in window]
        total = sum(sizes)
        per_second = total / elapsed if elapsed > 0 else 0.0
        rate, mean, low, high = (_bw_units(v, per_second) for v in (per_second, total / len(sizes), min(sizes),
                                                                     max(sizes)))
        print(f'{rate}/s from {len(sizes)} messages\n\tMessage size mean: {mean} min: {low} max: {high}',
              flush=True)
        return True
    print(f'Subscribed to [{monitor.topic}]', flush=True)
    return monitor.run(lambda _topic: on_message, report)


def cmd_delay(args: argparse.Namespace) -> int:
    from collections import deque

    from zros.errors import CliError, DecodeError
    from zros.message import deserialize
    monitor = _Monitor(args)
    delays: deque = deque(maxlen=args.window)
    state = {'new': False, 'any': False}

    def on_message(payload, info) -> None:
        state['any'] = True
        try:
            stamp = deserialize(payload, state['type']).header.stamp
        except DecodeError:
            return
        delays.append(info['received_timestamp'] - (stamp.sec * 1_000_000_000 + stamp.nanosec))
        state['new'] = True

    def check(msg_type) -> None:
        state['type'] = msg_type
        if 'header' not in msg_type._FIELDS:
            raise CliError(f"cannot compute the delay of '{monitor.topic}': {msg_type._TYPE} has no header")

    def report() -> bool:
        if not state['new']:
            if delays:
                print('no new messages', flush=True)
            return state['any']
        state['new'] = False
        mean, low, high, std = _stats(delays)
        print(f'average delay: {mean * 1e-9:.3f}\n\tmin: {low * 1e-9:.3f}s max: {high * 1e-9:.3f}s '
              f'std dev: {std * 1e-9:.5f}s window: {len(delays)}', flush=True)
        return True
    return monitor.run(lambda _topic: on_message, report, check=check)
