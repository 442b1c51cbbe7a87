"""`zros doctor [--report]` and `zros doctor hello`: ros2 doctor's checks for a zros system.

`zros doctor` looks at this machine's set-up (versions, the session settings in effect, whether
the hub or the configured routers answer) and at the running graph (duplicate node names, topics
whose endpoints disagree on the type or its definition, incompatible QoS pairs, simulated time
without a /clock). Errors make it exit 1; warnings are printed but do not fail it.

`zros doctor hello` checks that processes (on this or other hosts) hear each other: each one
publishes "hello, it's me HOST:PID" on a topic and prints whom it heard. Unlike ros2's, it sends
no UDP multicast: zros does not use multicast unless asked (ZROS_DISCOVERY=subnet).
"""
from __future__ import annotations

import argparse
import json
from typing import NamedTuple

from zros.graph_content import DEBUG_TOPICS, is_hidden

__all__ = ['add_arguments', 'Finding', 'run_checks']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('-r', '--report', action='store_true', help='Print a report of the set-up and the graph')
    parser.add_argument('-rf', '--report-failed', action='store_true', help='Print the report only if a check fails')
    parser.add_argument('-iw', '--include-warnings', action='store_true',
                        help='Count warnings as failures too (exit 1)')
    parser.add_argument('--json', action='store_true', help='Machine-readable output (findings and report)')
    parser.set_defaults(handler=cmd_doctor)
    sub = parser.add_subparsers(dest='doctor_verb', metavar='<command>')
    p = sub.add_parser('hello', help='Check that zros processes (on this and other hosts) hear each other')
    p.add_argument('-t', '--topic', default='/canyouhearme', help="Topic to publish to (default '/canyouhearme')")
    p.add_argument('-ep', '--emit-period', type=_positive_float, default=0.1, metavar='N',
                   help='Seconds between two hello messages (default 0.1)')
    p.add_argument('-pp', '--print-period', type=_positive_float, default=1.0, metavar='N',
                   help='Seconds between two summary tables (default 1.0)')
    p.add_argument('-1', '--once', action='store_true', help='Publish for one print period, print, then exit')
    p.set_defaults(handler=cmd_hello)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if value <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got '{text}'")
    return value


class Finding(NamedTuple):
    level: str      # 'ERROR' | 'WARNING'
    module: str     # 'config', 'network', 'nodes', 'topics', 'qos', 'clock'
    text: str


# -- set-up ------------------------------------------------------------------------------------------
def _versions() -> dict[str, str]:
    import platform
    from importlib import metadata

    from zros import __version__
    out = {'zros': __version__, 'python': platform.python_version()}
    for label, dist in (('zenoh', 'eclipse-zenoh'), ('msgpack', 'msgpack'), ('numpy', 'numpy'),
                        ('mcap', 'mcap'), ('pyyaml', 'PyYAML')):
        try:
            out[label] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[label] = 'not installed'
    return out


def _platform() -> dict[str, str]:
    import platform
    import socket
    return {'system': platform.system(), 'platform info': platform.platform(), 'release': platform.release(),
            'processor': platform.machine(), 'hostname': socket.gethostname()}


def _tcp_reachable(host: str, port: int, timeout: float = 0.5) -> bool:
    import socket
    try:
        with socket.create_connection((host, port), timeout=timeout):
            return True
    except OSError:
        return False


def _endpoint_address(endpoint: str) -> tuple[str, str, int] | None:
    """('tcp', host, port) for 'tcp/host:port' (also [v6]); None when it cannot be probed."""
    try:
        proto, rest = endpoint.split('/', 1)
        rest = rest.split('#')[0].split('?')[0]
        host, port = rest.rsplit(':', 1)
        return proto, host.strip('[]'), int(port)
    except ValueError:
        return None


def _config_checks(settings, findings: list[Finding]) -> dict[str, str]:
    """The settings in effect, and whether what they point at answers."""
    import os
    report = {
        'domain id': f"{settings.domain_id} ({settings.reasons.get('domain_id', 'ZROS_DOMAIN_ID')})",
        'discovery': settings.discovery,
        'connect': ', '.join(settings.connect) or '-',
        'listen': ', '.join(settings.listen) or '-',
        'config file': settings.config_file or '-',
    }
    if settings.config_file and not os.path.isfile(settings.config_file):
        findings.append(Finding('ERROR', 'config', f"ZROS_CONFIG '{settings.config_file}' does not exist"))
    if settings.uses_hub:
        address = _endpoint_address(settings.hub_endpoint)
        up = _tcp_reachable(address[1], address[2])
        report['hub endpoint'] = settings.hub_endpoint
        report['hub running'] = 'yes' if up else 'no (no zros process is running in this domain on this machine)'
    else:
        report['hub endpoint'] = '- (not used: ZROS_CONNECT or ZROS_DISCOVERY set)'
        report['hub running'] = '-'
    for endpoint in settings.connect:
        address = _endpoint_address(endpoint)
        if address is None or address[0] not in ('tcp', 'tls', 'ws', 'quic', 'udp'):
            continue
        if address[0] in ('tcp', 'tls', 'ws'):
            ok = _tcp_reachable(address[1], address[2])
            report[f'router {endpoint}'] = 'reachable' if ok else 'NOT reachable'
            if not ok:
                findings.append(Finding('ERROR', 'network', f'cannot reach {endpoint} (ZROS_CONNECT): '
                                        'is the router running and the address right?'))
    if settings.discovery == 'off' and not settings.connect and not settings.listen:
        findings.append(Finding('WARNING', 'config', 'ZROS_DISCOVERY=off without ZROS_CONNECT/ZROS_LISTEN: '
                                'this process can reach nobody'))
    return report


# -- the graph ---------------------------------------------------------------------------------------
def _graph_checks(entities, findings: list[Finding]) -> None:
    from zros.graph import EntityKind
    from zros.qos import QoSCompatibility, QoSProfile, qos_check_compatible
    nodes: dict[str, set] = {}
    for e in entities:
        if e.kind == EntityKind.NODE:
            nodes.setdefault(e.node_fqn, set()).add(e.node_key)
    for name, keys in sorted(nodes.items()):
        if len(keys) > 1:
            findings.append(Finding('ERROR', 'nodes', f"{len(keys)} nodes share the name '{name}' "
                                    '(their parameters and services cannot be told apart)'))
    topics: dict[str, list] = {}
    for e in entities:
        if e.kind in (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION):
            topics.setdefault(e.name, []).append(e)
    for topic, ends in sorted(topics.items()):
        by_type: dict[str, list] = {}
        for e in ends:
            by_type.setdefault(e.type, []).append(e)
        if len(by_type) > 1:
            detail = '; '.join(f"{t} ({', '.join(sorted({_who(e) for e in es}))})" for t, es in sorted(by_type.items()))
            findings.append(Finding('ERROR', 'topics', f"topic '{topic}' has more than one type: {detail}"))
            continue
        hashes: dict[str, list] = {}
        for e in ends:
            if e.type_hash:
                hashes.setdefault(e.type_hash, []).append(e)
        if len(hashes) > 1:
            detail = '; '.join(f"{h} ({', '.join(sorted({_who(e) for e in es}))})" for h, es in sorted(hashes.items()))
            findings.append(Finding('ERROR', 'topics', f"topic '{topic}' ({ends[0].type}): the endpoints use "
                                    f'different definitions of the type (hashes {detail})'))
        pubs = [e for e in ends if e.kind == EntityKind.PUBLISHER]
        subs = [e for e in ends if e.kind == EntityKind.SUBSCRIPTION]
        reported = set()
        for p in pubs:
            for s in subs:
                level, reason = qos_check_compatible(QoSProfile.from_token(p.qos), QoSProfile.from_token(s.qos))
                key = (_who(p), _who(s), reason)
                if level == QoSCompatibility.ERROR and key not in reported:
                    reported.add(key)
                    findings.append(Finding('ERROR', 'qos', f"topic '{topic}': incompatible QoS between publisher "
                                            f'{_who(p)} and subscription {_who(s)}: '
                                            f"{reason.removeprefix('ERROR: ').rstrip(';')}"))
        if pubs and not subs and topic not in DEBUG_TOPICS and not is_hidden(topic):
            findings.append(Finding('WARNING', 'topics', f"publisher without subscriber on '{topic}'"))
        if subs and not pubs and topic == '/clock':
            users = ', '.join(sorted({_who(e) for e in subs}))
            findings.append(Finding('WARNING', 'clock', f'nodes use simulated time (use_sim_time) but nothing '
                                    f'publishes /clock: {users}; their clocks stand still'))


def _who(entity) -> str:
    return entity.node_fqn


def _clock_checks(findings: list[Finding]) -> dict[str, str]:
    import time
    wall0, mono0 = time.time(), time.monotonic()
    time.sleep(0.2)
    wall1, mono1 = time.time(), time.monotonic()
    drift = (wall1 - wall0) - (mono1 - mono0)
    if abs(drift) > 0.02:
        findings.append(Finding('WARNING', 'clock', f'the wall clock moved {drift * 1000:+.0f} ms against the '
                                'monotonic clock in 0.2 s (NTP step or manual change?); timestamps jump'))
    if wall1 < 1577836800:  # 2020-01-01
        findings.append(Finding('WARNING', 'clock', f"the wall clock reads {time.strftime('%Y-%m-%d', time.gmtime(wall1))}: "
                                'is it set? source timestamps and bag times will be wrong'))
    return {'wall clock': time.strftime('%Y-%m-%d %H:%M:%S %Z', time.localtime(wall1)),
            'wall - monotonic drift (0.2 s)': f'{drift * 1e6:+.0f} us'}


def run_checks() -> tuple[list[Finding], dict[str, dict]]:
    """Every check; returns (findings, report sections)."""
    from zros.config import settings_from_env
    from zros.errors import ZrosError
    findings: list[Finding] = []
    report: dict[str, dict] = {'PLATFORM INFORMATION': _platform(), 'VERSIONS': _versions()}
    try:
        settings = settings_from_env()
    except ZrosError as exc:
        findings.append(Finding('ERROR', 'config', str(exc)))
        return findings, report
    report['ZROS CONFIGURATION'] = _config_checks(settings, findings)
    report['CLOCK'] = _clock_checks(findings)
    hub_down = settings.uses_hub and report['ZROS CONFIGURATION']['hub running'] != 'yes'
    if hub_down:
        report['NETWORK'] = {'graph': 'not checked: no zros process is running in this domain'}
        return findings, report
    from zros.cli.common import cli_context, graph_entities
    try:
        with cli_context() as ctx:
            entities = graph_entities(ctx)
            own = str(ctx.session.info.zid())
            report['NETWORK'] = {'session zid': own,
                                 'peers connected': str(len(list(ctx.session.info.peers_zid()))),
                                 'routers connected': str(len(list(ctx.session.info.routers_zid())))}
    except ZrosError as exc:
        findings.append(Finding('ERROR', 'network', f'cannot open a Zenoh session: {exc}'))
        return findings, report
    entities = [e for e in entities if e.zid != own]
    if not settings.uses_hub and report['NETWORK']['peers connected'] == '0' \
            and report['NETWORK']['routers connected'] == '0':
        findings.append(Finding('WARNING', 'network', 'connected to no peer and no router: the graph is empty'))
    _graph_checks(entities, findings)
    report['NODES'] = _node_report(entities)
    report['TOPIC LIST'] = _topic_report(entities)
    return findings, report


def _node_report(entities) -> dict[str, str]:
    from zros.graph import EntityKind
    names = sorted({e.node_fqn for e in entities if e.kind == EntityKind.NODE and not is_hidden(e.node_fqn)})
    return {f'node {i + 1}': name for i, name in enumerate(names)} or {'nodes': '(none)'}


def _topic_report(entities) -> list[dict[str, str]]:
    from zros.graph import EntityKind
    topics = sorted({e.name for e in entities if e.kind in (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION)
                     and not is_hidden(e.name)})
    return [{'topic': t,
             'publisher count': str(sum(1 for e in entities if e.kind == EntityKind.PUBLISHER and e.name == t)),
             'subscriber count': str(sum(1 for e in entities if e.kind == EntityKind.SUBSCRIPTION and e.name == t))}
            for t in topics]


def _print_report(report: dict) -> None:
    for title, section in report.items():
        print(f'\n   {title}')
        rows = section if isinstance(section, list) else [section]
        for row in rows:
            width = max((len(k) for k in row), default=0)
            for key, value in row.items():
                print(f'{key:<{width}} : {value}')
            if isinstance(section, list):
                print()
    print()


def cmd_doctor(args: argparse.Namespace) -> int:
    findings, report = run_checks()
    failing = [f for f in findings if f.level == 'ERROR' or (args.include_warnings and f.level == 'WARNING')]
    modules = ['config', 'network', 'nodes', 'topics', 'qos', 'clock']
    failed_modules = sorted({f.module for f in failing}, key=modules.index)
    if args.json:
        print(json.dumps({'findings': [f._asdict() for f in findings], 'failed_modules': failed_modules,
                          'report': report}))
        return 1 if failing else 0
    if args.report or (args.report_failed and failing):
        _print_report(report)
    for f in findings:
        print(f'{f.level}: [{f.module}] {f.text}')
    if failing:
        print(f'{len(failed_modules)}/{len(modules)} check(s) failed')
        print(f"Failed modules: {' '.join(failed_modules)}")
        return 1
    print(f'All {len(modules)} checks passed')
    return 0


# -- hello ---------------------------------------------------------------------------------------------
def _hello_id() -> str:
    import os
    import socket
    return f'{socket.gethostname()}:{os.getpid()}'


def cmd_hello(args: argparse.Namespace) -> int:
    import threading
    import time

    from zros.cli.common import cli_context, cli_node
    from zros.executors import SingleThreadedExecutor
    from zros.names import expand_topic_name
    from zros.typesupport import get_message
    topic = expand_topic_name(args.topic, 'zros', '/')
    string_type = get_message('std_msgs/msg/String')
    me = _hello_id()
    lock = threading.Lock()
    heard: dict[str, int] = {}
    published = [0]

    def on_hello(msg) -> None:
        sender = msg.data.split()[-1] if msg.data.split() else ''
        if sender and sender != me:
            with lock:
                heard[sender] = heard.get(sender, 0) + 1

    def print_summary() -> None:
        with lock:
            table, count = dict(heard), published[0]
            heard.clear()
            published[0] = 0
        print('MULTIMACHINE COMMUNICATION SUMMARY')
        print(f'Topic: {topic}, Published Msg Count: {count}')
        print('Subscribed from:')
        print('{:<15} {:<20} {:<10}'.format('', 'Hostname', f'Msg Count /{args.print_period}s'))
        for name, n in sorted(table.items()):
            print('{:<15} {:<20} {:<10}'.format('', name, n))
        print('-' * 60, flush=True)

    with cli_context() as ctx:
        node = cli_node(ctx)
        publisher = node.create_publisher(string_type, topic, 10)
        node.create_subscription(string_type, topic, on_hello, 10)
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(node)
        hello = string_type(data=f"hello, it's me {me}")
        start = time.monotonic()
        next_emit = start
        next_print = start + args.print_period
        while True:
            now = time.monotonic()
            if now >= next_emit:
                publisher.publish(hello)
                with lock:
                    published[0] += 1
                next_emit = max(next_emit + args.emit_period, now)
            if now >= next_print:
                print_summary()
                if args.once:
                    return 0
                next_print = max(next_print + args.print_period, now)
            executor.spin_once(timeout_sec=max(0.0, min(next_emit, next_print) - time.monotonic()))
