"""`zros router`: run a Zenoh router (Zenoh's own routing, in router mode) in this process.

    zros router                                   # listens on tcp/0.0.0.0:7447 (every IPv4 interface)
    zros router --listen tcp/0.0.0.0:7447 --listen tls/0.0.0.0:7448 --config tls-router.json5
    zros router --connect tcp/10.0.0.2:7447       # link to another router (router to router)
    zros router --domain 3                        # also be domain 3's loopback hub on this host

Other hosts' zros processes point at it with ZROS_CONNECT=tcp/<this host>:7447; they are peers,
and the router introduces them to each other (gossip), so they then talk directly and keep
talking if the router restarts. A Zenoh router does not forward traffic between two peers that
cannot reach each other: those need client mode (a ZROS_CONFIG file with mode "client").

Listening on tcp/0.0.0.0:7447 also covers 127.0.0.1:7447, domain 0's loopback hub port, so zros
processes of domain 0 started on this host without any setting join the router by themselves.
`--domain N` adds tcp/127.0.0.1:<7447+N> for domain N's. Failover brokering and every other
routing setting keep Zenoh's defaults, so plain Zenoh clients work through it as through zenohd.

The router also answers `@zros/v1/<domain>/graph` for every domain, as the loopback hub does,
so a fresh `zros node list` through it gets the whole graph in one round trip.
"""
from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import time

__all__ = ['add_arguments', 'main', 'build_router_config', 'Router', 'RouterGraph', 'DEFAULT_LISTEN']

DEFAULT_LISTEN = 'tcp/0.0.0.0:7447'
# The graph is served only once peers that were linked to a previous router run have had time
# to come back (their connect retry is 1 s at most): until then a reader collects tokens itself.
GRAPH_WARMUP_S = 1.5


def _endpoint_list(values: list[str] | None, what: str) -> list[str]:
    from zros.config import validate_endpoint
    out: list[str] = []
    for value in values or []:
        out.extend(validate_endpoint(e.strip(), what) for e in value.split(',') if e.strip())
    return out


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = ('examples:\n  zros router\n  zros router --listen tcp/0.0.0.0:7447 --connect tcp/10.0.0.2:7447\n'
                     '  zros router --config configs/zenoh/tls-router.json5\n'
                     'then, on other hosts: ZROS_CONNECT=tcp/<this host>:7447 zros node list')
    parser.add_argument('--listen', action='append', metavar='EP',
                        help=f'endpoint to listen on, repeatable or comma-separated (default: {DEFAULT_LISTEN}, '
                             'or the config file\'s)')
    parser.add_argument('--connect', action='append', metavar='EP',
                        help='endpoint of another router to link to, repeatable or comma-separated')
    parser.add_argument('--config', metavar='FILE', help='a Zenoh JSON5 config file (TLS, access control, ...); '
                                                         '--listen and --connect replace its endpoints')
    parser.add_argument('--domain', type=int, metavar='N', default=None,
                        help='also listen on domain N\'s loopback hub port, tcp/127.0.0.1:<7447+N>, so that '
                             'this host\'s zros processes of domain N join the router without settings')
    parser.add_argument('-v', '--verbose', action='store_true', help='print nodes as they join and leave')
    parser.set_defaults(handler=main)


def _covers(listen: list[str], port: int) -> bool:
    """Whether a listen endpoint already binds 127.0.0.1:<port> (0.0.0.0, [::] or 127.0.0.1)."""
    for endpoint in listen:
        proto, _, address = endpoint.partition('/')
        host, _, p = address.split('#')[0].split('?')[0].rpartition(':')
        if proto == 'tcp' and p == str(port) and host in ('0.0.0.0', '[::]', '127.0.0.1', 'localhost'):
            return True
    return False


def build_router_config(*, listen: list[str], connect: list[str], config_file: str | None,
                        domain: int | None) -> tuple[object, list[str]]:
    """The router's Zenoh config and its listen endpoints."""
    import zenoh
    from zros.config import HUB_BASE_PORT, _load_file
    from zros.errors import ZrosError
    loaded = None
    if config_file:
        try:
            loaded = _load_file(config_file)
        except ZrosError as exc:   # the loader's one-line errors name ZROS_CONFIG
            raise ZrosError(str(exc).replace('ZROS_CONFIG', '--config', 1)) from None
        config = zenoh.Config.from_json5(str(loaded.config))
    else:
        config = zenoh.Config()

    def put(key: str, value: object) -> None:
        config.insert_json5(key, json.dumps(value))

    def unset(key: str) -> bool:
        return loaded is None or loaded.get(key) is None

    put('mode', 'router')
    listen = list(listen) or list(loaded.listen if loaded else []) or [DEFAULT_LISTEN]
    if domain is not None and not _covers(listen, HUB_BASE_PORT + domain):
        listen.append(f'tcp/127.0.0.1:{HUB_BASE_PORT + domain}')
    put('listen/endpoints', listen)
    if connect:
        put('connect/endpoints', connect)
    if unset('scouting/multicast/enabled'):
        put('scouting/multicast/enabled', False)   # nothing on the LAN unless the file asks
    if unset('scouting/gossip/enabled'):
        put('scouting/gossip/enabled', True)       # how peers learn each other's locators
    if unset('timestamping/enabled'):
        put('timestamping/enabled', True)
    return config, listen


class RouterGraph:
    """Every zros domain's graph as the router sees it (every peer and client links to it),
    served on `@zros/v1/<domain>/graph` like the loopback hub's `zros.graph.GraphService`."""

    def __init__(self, session, *, verbose: bool = False, warmup: float = GRAPH_WARMUP_S) -> None:
        self._lock = threading.Lock()
        self._keys: dict[str, set[str]] = {}
        self._verbose = verbose
        self._ready_at = time.monotonic() + warmup
        self._subscriber = session.liveliness().declare_subscriber('@zros/v1/**', self._on_token, history=True)
        self._queryable = session.declare_queryable('@zros/v1/*/graph', self._on_query, complete=True)

    def _on_token(self, sample) -> None:
        import zenoh
        key = str(sample.key_expr)
        parts = key.split('/')
        if len(parts) < 9:
            return
        domain = parts[2]
        gone = sample.kind == zenoh.SampleKind.DELETE
        with self._lock:
            keys = self._keys.setdefault(domain, set())
            (keys.discard if gone else keys.add)(key)
        if self._verbose and parts[6] == 'NN':
            ns = parts[7].replace('%', '/').rstrip('/')
            print(f"{'-' if gone else '+'} node {ns}/{parts[8]} (domain {domain}, zid {parts[3]})", flush=True)

    def _on_query(self, query) -> None:
        import msgpack
        try:
            if time.monotonic() < self._ready_at:
                return   # no reply: the reader falls back to collecting tokens itself
            domain = str(query.key_expr).split('/')[2]
            with self._lock:
                keys = sorted(self._keys.get(domain, ()))
            query.reply(query.key_expr, msgpack.packb(keys))
        finally:
            query.drop()

    def close(self) -> None:
        for entity in (self._queryable, self._subscriber):
            try:
                entity.undeclare()
            except Exception:  # noqa: BLE001 - the session may already be closing
                pass


def _ipv4_addresses() -> list[str]:
    """This host's IPv4 interface addresses, loopback last (Linux: SIOCGIFADDR per interface)."""
    import fcntl
    import socket
    import struct
    found: list[str] = []
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            for _, name in socket.if_nameindex():
                try:
                    packed = fcntl.ioctl(probe.fileno(), 0x8915, struct.pack('256s', name.encode()[:15]))
                except OSError:
                    continue   # an interface without an IPv4 address
                found.append(socket.inet_ntoa(packed[20:24]))
    except (OSError, AttributeError):
        return []
    return sorted(set(found), key=lambda a: (a.startswith('127.'), a))


def reachable_endpoints(listen: list[str]) -> list[str]:
    """Where other hosts can dial the router: 0.0.0.0 listeners expanded to the interfaces."""
    out: list[str] = []
    for endpoint in listen:
        proto, _, address = endpoint.partition('/')
        host, _, port = address.split('#')[0].split('?')[0].rpartition(':')
        if host == '0.0.0.0':
            out.extend(f'{proto}/{a}:{port}' for a in _ipv4_addresses() if not a.startswith('127.'))
        elif not (host.startswith('127.') or host in ('localhost', '[::1]')):
            out.append(endpoint)
    return out


def _explain_listen_error(text: str, listen: list[str]) -> str:
    from zros.config import HUB_BASE_PORT
    if 'in use' in text.lower() or 'AddrInUse' in text:
        hint = ''
        for endpoint in listen:
            port = endpoint.split('#')[0].split('?')[0].rpartition(':')[2]
            if port.isdigit() and HUB_BASE_PORT <= int(port) <= HUB_BASE_PORT + 232:
                hint = (f' (a zros process of domain {int(port) - HUB_BASE_PORT} may hold it as its loopback hub: '
                        'start the router first, or choose another port with --listen)')
        return f'cannot listen on {", ".join(listen)}: address in use{hint}'
    return f'cannot start the router: {text}'


class Router:
    """A Zenoh router and its graph service in this process (`zros router`, `zros launch --router`)."""

    def __init__(self, *, listen: list[str] = (), connect: list[str] = (), config_file: str | None = None,
                 domain: int | None = None, verbose: bool = False) -> None:
        import zenoh
        from zros.config import _zenoh_error_text
        from zros.errors import CliError
        if domain is not None and not 0 <= domain <= 232:
            raise CliError(f'--domain must be within 0-232, got {domain}')
        self.connect = list(connect)
        config, self.listen = build_router_config(listen=list(listen), connect=self.connect,
                                                  config_file=config_file, domain=domain)
        try:
            self.session = zenoh.open(config)
        except zenoh.ZError as exc:
            raise CliError(_explain_listen_error(_zenoh_error_text(exc), self.listen)) from None
        try:
            self.graph = RouterGraph(self.session, verbose=verbose)
        except BaseException:
            self.session.close()
            raise

    def describe(self) -> list[str]:
        lines = [f'zros router {self.session.info.zid()} (Zenoh router mode)']
        lines += [f'listening on {endpoint}' for endpoint in self.listen]
        reachable = reachable_endpoints(self.listen)
        if reachable:
            lines.append('reachable at ' + ', '.join(reachable))
        lines += [f'connecting to {endpoint}' for endpoint in self.connect]
        if reachable:
            lines.append(f'on other hosts: ZROS_CONNECT={reachable[0]} zros node list')
        return lines

    def close(self) -> None:
        self.graph.close()
        try:
            self.session.close()
        except Exception:  # noqa: BLE001 - closing at exit
            pass


def main(args: argparse.Namespace) -> int:
    from zros.config import security_config_file
    # SROS2's ROS_SECURITY_* variables: the keystore's router enclave (zros security create_keystore).
    config_file = args.config or security_config_file(default_enclave='router')
    router = Router(listen=_endpoint_list(args.listen, '--listen'), connect=_endpoint_list(args.connect, '--connect'),
                    config_file=config_file, domain=args.domain, verbose=args.verbose)
    stop = threading.Event()
    previous = {s: signal.signal(s, lambda *_: stop.set()) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        for line in router.describe():
            print(line, flush=True)
        while not stop.wait(0.5):
            pass
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        router.close()
        print('zros router: stopped', file=sys.stderr, flush=True)
    return 0
