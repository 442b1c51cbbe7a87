"""Which Zenoh session a zros process opens: one setting for one machine or many.

Zero set-up on one machine (docs/architecture.md §5): the first zros process of a domain binds the domain's
hub port on loopback (7447 + domain id) and every later process connects to it; Zenoh's gossip
then links the processes to each other directly, so the hub is only a meeting point. When the
hub process exits, the others stay linked, and the next process to start takes the port over
(the others reconnect to it within a second). Nothing leaves loopback unless asked.

Environment (each also a `zros run` / `zros launch` option, see docs/multi-machine.md):
    ZROS_DOMAIN_ID   domain, isolates systems (default 0; ROS_DOMAIN_ID is read when unset)
    ZROS_CONNECT     comma-separated endpoints to connect to (e.g. tcp/192.168.1.10:7447);
                     disables the loopback hub
    ZROS_LISTEN      comma-separated endpoints to listen on
    ZROS_DISCOVERY   localhost (default) | subnet (multicast scouting) | off
    ZROS_CONFIG      a Zenoh JSON5 config file, applied first; the settings above override it
    ROS_SECURITY_ENABLE=true with ROS_SECURITY_KEYSTORE (SROS2's words): when ZROS_CONFIG is
                     unset, the config is the enclave's `tls.json5` in the keystore that
                     `zros security create_keystore/create_enclave` made (the enclave from
                     `--ros-args --enclave`, ROS_SECURITY_ENCLAVE_OVERRIDE, else '/');
                     ROS_SECURITY_STRATEGY=Enforce makes a missing enclave an error;
                     without ZROS_CONNECT the loopback hub runs over mutual TLS (below)

What each setting does, and the rules that pick the session's endpoints:
- localhost: the loopback hub, as above. A process that finds the hub port held by a Zenoh
  *router* (`zros router` listens on tcp/0.0.0.0:7447, which is domain 0's hub port) joins
  it as if ZROS_CONNECT named it, so that it is reachable from the router's other hosts.
- subnet: Zenoh multicast scouting on the LAN, and listening on every IPv4 interface.
- off: no hub and no multicast: the process meets only what its ZROS_CONNECT / ZROS_LISTEN
  endpoints lead to (Zenoh's gossip over those links still introduces peers to each other,
  which they need: a Zenoh router does not forward traffic between two peers).
- Where a peer listens, unless ZROS_LISTEN or the ZROS_CONFIG file says: a process of the
  loopback hub on tcp/127.0.0.1:0 (the hub itself on its port), and one with ZROS_CONNECT or
  discovery subnet on tcp/0.0.0.0:0 (an ephemeral port on every IPv4 interface), so that the
  peers it meets through a router can link to it directly; discovery off without endpoints
  stays on tcp/127.0.0.1:0. A client (mode from the file) does not listen.
- ROS_SECURITY_ENABLE=true on one machine (no ZROS_CONNECT, discovery localhost): SROS2's steps
  start no router, so the enclave's certificate is used for the loopback hub itself: the hub
  and every link between processes are mutual TLS (tls/127.0.0.1), and only holders of a
  certificate from the keystore's CA join. A process that finds the keystore's router on the
  hub port (`zros router`, domain 0) becomes its client, as the enclave's file says, so the
  router's access control sees every message. With ZROS_CONNECT the enclave's file rules: a
  client of the router named there.
- ZROS_CONFIG is loaded first; ZROS_CONNECT, ZROS_LISTEN and ZROS_DISCOVERY then replace the
  file's connect endpoints, listen endpoints and multicast setting when they are set. zros
  always enables `timestamping` (its transient-local cache needs it); gossip scouting and
  the connect retry period get zros's values only where the file leaves them unset. A file
  with connect endpoints, or in `client` mode, never makes the process a loopback hub.

`SessionSettings.reasons` says where each setting came from ('ZROS_CONNECT', 'ZROS_CONFIG',
'default', ...), which is what `zros doctor` shows.
"""
from __future__ import annotations

import json
import os
import re
import socket
import sys
from dataclasses import dataclass, field, replace

from zros.errors import RCLError, ZrosError
from zros.priority import ENV as PRIORITY_ENV, parse_topic_priorities

__all__ = ['SessionSettings', 'settings_from_env', 'security_config_file', 'HUB_BASE_PORT', 'open_session', 'build_config',
           'validate_endpoint', 'DISCOVERY_MODES', 'SETTINGS_ENV', 'SESSION_OPTIONS', 'add_session_options',
           'apply_session_options', 'split_session_options', 'hub_port_free', 'LOOPBACK_LEASE_MS']

HUB_BASE_PORT = 7447
DISCOVERY_MODES = ('localhost', 'subnet', 'off')
MODES = ('peer', 'client', 'router')
# Every environment variable that decides the session (what `zros run/launch` options set).
SETTINGS_ENV = ('ZROS_DOMAIN_ID', 'ZROS_CONNECT', 'ZROS_LISTEN', 'ZROS_DISCOVERY', 'ZROS_CONFIG')

# Zenoh 1.x link protocols (those built into the eclipse-zenoh wheel and the optional ones).
_PROTOCOLS = ('tcp', 'udp', 'tls', 'quic', 'ws', 'unixsock-stream', 'unixpipe', 'serial', 'vsock')
_IP_PROTOCOLS = ('tcp', 'udp', 'tls', 'quic', 'ws')
_ALL_IPV4 = 'tcp/0.0.0.0:0'
_LOOPBACK_ANY = 'tcp/127.0.0.1:0'


@dataclass(frozen=True)
class SessionSettings:
    domain_id: int = 0
    connect: tuple[str, ...] = ()
    listen: tuple[str, ...] = ()
    discovery: str = 'localhost'
    config_file: str | None = None
    mode: str = 'peer'          # the Zenoh mode: peer, or what the ZROS_CONFIG file says
    reasons: dict[str, str] = field(default_factory=dict, compare=False)
    #: The loopback hub and links run over mutual TLS with the config file's (an enclave's)
    #: certificate: ROS_SECURITY_ENABLE on one machine.
    tls: bool = False

    @property
    def link(self) -> str:
        """The protocol of the loopback hub and of the links a peer listens for."""
        return 'tls' if self.tls else 'tcp'

    @property
    def hub_endpoint(self) -> str:
        return f'{self.link}/127.0.0.1:{HUB_BASE_PORT + self.domain_id}'

    @property
    def uses_hub(self) -> bool:
        return self.discovery == 'localhost' and not self.connect and self.mode == 'peer'

    def describe(self) -> list[tuple[str, str, str]]:
        """(setting, value, where it came from) rows, for `zros doctor` and error messages."""
        rows = [('domain', str(self.domain_id), self.reasons.get('domain_id', 'default')),
                ('mode', self.mode, self.reasons.get('mode', 'default')),
                ('discovery', self.discovery, self.reasons.get('discovery', 'default')),
                ('connect', ', '.join(self.connect) or '-', self.reasons.get('connect', 'default')),
                ('listen', ', '.join(self.listen) or '-', self.reasons.get('listen', 'default')),
                ('config file', self.config_file or '-', self.reasons.get('config_file', 'default'))]
        if self.uses_hub:
            rows.append(('hub', self.hub_endpoint, 'discovery localhost without endpoints'))
        return rows


def _split(value: str | None) -> tuple[str, ...]:
    return tuple(p.strip() for p in (value or '').split(',') if p.strip())


def validate_endpoint(endpoint: str, what: str = 'endpoint') -> str:
    """`endpoint` if it is a well-formed Zenoh locator (`proto/address[?metadata][#config]`),
    else ZrosError with a one-line reason and an example."""
    example = 'e.g. tcp/192.168.1.10:7447'
    if '/' not in endpoint:
        hint = f" (did you mean 'tcp/{endpoint}'?)" if re.fullmatch(r'[\w.\-\[\]:]+:\d+', endpoint) else ''
        raise ZrosError(f"{what}: '{endpoint}' is not a Zenoh endpoint{hint}; expected PROTOCOL/ADDRESS, {example}")
    proto, address = endpoint.split('/', 1)
    if proto not in _PROTOCOLS:
        raise ZrosError(f"{what}: '{endpoint}' has an unknown protocol '{proto}' "
                        f"(one of {', '.join(_PROTOCOLS)}; {example})")
    address = re.split(r'[?#]', address, maxsplit=1)[0]
    if not address:
        raise ZrosError(f"{what}: '{endpoint}' has no address; {example}")
    if proto in _IP_PROTOCOLS:
        host, sep, port = address.rpartition(':')
        if not sep or not host or not port.isdigit() or not 0 <= int(port) <= 65535:
            raise ZrosError(f"{what}: '{endpoint}' needs HOST:PORT with a port 0-65535; {example}")
        if host.startswith('[') != host.endswith(']'):
            raise ZrosError(f"{what}: '{endpoint}': write an IPv6 address in brackets, e.g. tcp/[::1]:7447")
    return endpoint


def _zenoh_error_text(exc: BaseException) -> str:
    """Zenoh's errors can span lines and carry a Rust source position: one line, no position."""
    text = ' '.join(str(exc).split())
    return re.sub(r'\s*at /\S+\.rs:\d+\.?', '', text).strip() or type(exc).__name__


class _FileConfig:
    """What zros needs to know of a ZROS_CONFIG file: its mode and endpoints, and which of the
    settings zros fills in it left unset (null in Zenoh's view of the loaded config)."""

    def __init__(self, path: str) -> None:
        import zenoh
        if not os.path.isfile(path):
            raise ZrosError(f"ZROS_CONFIG: no such file '{path}'")
        try:
            self.config = zenoh.Config.from_file(path)
        except Exception as exc:  # noqa: BLE001 - zenoh raises its own error type with the reason
            raise ZrosError(f"ZROS_CONFIG: cannot load '{path}': {_zenoh_error_text(exc)}") from None
        self.values = json.loads(str(self.config))
        default_listen = json.loads(str(zenoh.Config())).get('listen', {}).get('endpoints')
        mode = self.values.get('mode') or 'peer'
        if mode not in MODES:
            raise ZrosError(f"ZROS_CONFIG: '{path}': mode must be one of {', '.join(MODES)}, got '{mode}'")
        self.mode = mode
        self.connect = self._endpoints(self.values.get('connect', {}).get('endpoints'), mode)
        listen = self.values.get('listen', {}).get('endpoints')
        self.listen = () if listen == default_listen else self._endpoints(listen, mode)
        self.multicast = self._per_mode(self.get('scouting/multicast/enabled'), mode)

    @staticmethod
    def _per_mode(value: object, mode: str) -> object:
        return value.get(mode) if isinstance(value, dict) else value

    @classmethod
    def _endpoints(cls, value: object, mode: str) -> tuple[str, ...]:
        value = cls._per_mode(value, mode)
        return tuple(str(v) for v in value) if isinstance(value, list) else ()

    def get(self, key: str) -> object:
        node: object = self.values
        for part in key.split('/'):
            if not isinstance(node, dict):
                return None
            node = node.get(part)
        return node


_file_cache: dict[tuple[str, float], _FileConfig] = {}


def _load_file(path: str) -> _FileConfig:
    try:
        stamp = os.path.getmtime(path)
    except OSError:
        stamp = -1.0
    key = (os.path.abspath(path), stamp)
    if key not in _file_cache:
        _file_cache[key] = _FileConfig(path)
    return _file_cache[key]


def security_config_file(env: os._Environ | dict | None = None, enclave: str | None = None, *,
                         default_enclave: str = '/') -> str | None:
    """The Zenoh config file SROS2's variables ask for, or None when security is off.

    ROS_SECURITY_ENABLE=true and ROS_SECURITY_KEYSTORE=DIR select `DIR/enclaves/<enclave>/tls.json5`
    (an mTLS client of the keystore's router; for the router, its mTLS listener). The enclave is
    ROS_SECURITY_ENCLAVE_OVERRIDE, else `enclave` (`--ros-args --enclave`), else `default_enclave`.
    A missing enclave is an error under ROS_SECURITY_STRATEGY=Enforce; under Permissive (the
    default, as in SROS2) the process warns and runs without security.
    """
    env = os.environ if env is None else env
    if (env.get('ROS_SECURITY_ENABLE') or '').strip().lower() != 'true':
        return None
    keystore = (env.get('ROS_SECURITY_KEYSTORE') or '').strip()
    if not keystore:
        raise ZrosError('ROS_SECURITY_ENABLE=true needs ROS_SECURITY_KEYSTORE, a directory made by '
                        '`zros security create_keystore DIR`')
    name = (env.get('ROS_SECURITY_ENCLAVE_OVERRIDE') or enclave or default_enclave).strip() or '/'
    path = os.path.join(os.path.expanduser(keystore), 'enclaves', *[p for p in name.split('/') if p], 'tls.json5')
    if os.path.isfile(path):
        return path
    if name.strip('/'):
        problem = (f"no enclave '{name}' in the keystore '{keystore}' "
                   f"(create it with: zros security create_enclave {keystore} {name})")
    else:
        problem = ('no enclave given: pass `--ros-args --enclave NAME` or set ROS_SECURITY_ENCLAVE_OVERRIDE=NAME '
                   f"(enclaves of '{keystore}': zros security list_enclaves {keystore})")
    if (env.get('ROS_SECURITY_STRATEGY') or '').strip().lower() == 'enforce':
        raise ZrosError(problem)
    print(f'[WARN] zros: {problem}; running without security (ROS_SECURITY_STRATEGY is not Enforce)',
          file=sys.stderr)
    return None


def settings_from_env(env: os._Environ | dict | None = None, *, domain_id: int | None = None,
                      enclave: str | None = None) -> SessionSettings:
    """The session settings in effect for this environment; ZrosError (one line) on a bad value.
    `enclave` is the process's `--ros-args --enclave` (see `security_config_file`)."""
    env = os.environ if env is None else env
    reasons: dict[str, str] = {}
    if domain_id is None:
        name = 'ZROS_DOMAIN_ID' if env.get('ZROS_DOMAIN_ID') else 'ROS_DOMAIN_ID' if env.get('ROS_DOMAIN_ID') else ''
        raw = (env.get(name) if name else '0').strip()
        try:
            domain_id = int(raw)
        except ValueError:
            raise ZrosError(f"{name} must be an integer 0-232, got '{raw}'") from None
        if not 0 <= domain_id <= 232:
            raise ZrosError(f'{name} must be within 0-232, got {domain_id}')
        reasons['domain_id'] = name or 'default'
    else:
        reasons['domain_id'] = 'argument'
    if not 0 <= domain_id <= 232:
        raise RCLError(f'domain id must be within 0-232, got {domain_id}')
    # per-topic priorities (zros.priority): a bad rule stops the process here, before any node
    parse_topic_priorities(env.get(PRIORITY_ENV, ''))
    thread = (env.get('ZROS_CALLBACK_THREAD') or '').strip()
    if thread and thread not in ('spin', 'zenoh'):
        raise ZrosError(f"ZROS_CALLBACK_THREAD must be 'spin' (the default) or 'zenoh', got '{thread}'")

    config_file = (env.get('ZROS_CONFIG') or '').strip() or None
    secure = False
    if config_file:
        reasons['config_file'] = 'ZROS_CONFIG'
    else:
        config_file = security_config_file(env, enclave)
        if config_file:
            reasons['config_file'] = 'ROS_SECURITY_KEYSTORE'
            secure = True
    loaded = _load_file(config_file) if config_file else None

    def endpoints(variable: str, from_file: tuple[str, ...]) -> tuple[str, ...]:
        raw = env.get(variable)
        if raw is not None and raw.strip():
            reasons[variable[5:].lower()] = variable
            return tuple(validate_endpoint(e, variable) for e in _split(raw))
        if from_file:
            reasons[variable[5:].lower()] = 'ZROS_CONFIG'
            return from_file
        reasons[variable[5:].lower()] = 'default'
        return ()

    connect = endpoints('ZROS_CONNECT', loaded.connect if loaded else ())
    listen = endpoints('ZROS_LISTEN', loaded.listen if loaded else ())

    raw = (env.get('ZROS_DISCOVERY') or '').strip().lower()
    if raw:
        if raw not in DISCOVERY_MODES:
            raise ZrosError(f"ZROS_DISCOVERY must be one of {', '.join(DISCOVERY_MODES)}, got '{raw}'")
        discovery, reasons['discovery'] = raw, 'ZROS_DISCOVERY'
    elif loaded is not None and loaded.multicast is True:
        discovery, reasons['discovery'] = 'subnet', 'ZROS_CONFIG (multicast scouting enabled)'
    else:
        discovery, reasons['discovery'] = 'localhost', 'default'

    mode = loaded.mode if loaded else 'peer'
    reasons['mode'] = 'ZROS_CONFIG' if loaded and loaded.values.get('mode') else 'default'
    tls = False
    if secure and mode == 'client' and reasons['connect'] != 'ZROS_CONNECT' and discovery == 'localhost':
        # SROS2's steps start no router: on one machine the enclave makes the loopback hub mTLS.
        mode, connect, tls = 'peer', (), True
        reasons['mode'] = reasons['connect'] = 'ROS_SECURITY_ENABLE without ZROS_CONNECT: mTLS on loopback'
    if mode == 'client' and not connect and discovery != 'subnet':
        raise ZrosError('a client-mode session needs a router to connect to: set ZROS_CONNECT '
                        '(or connect/endpoints in the ZROS_CONFIG file)')
    return SessionSettings(domain_id=domain_id, connect=connect, listen=listen, discovery=discovery,
                           config_file=config_file, mode=mode, reasons=reasons, tls=tls)


# -- the same settings as command-line options (`zros run`, `zros launch`) ---------------------
# option -> (environment variable, metavar, help); --connect and --listen may repeat.
SESSION_OPTIONS = {
    '--domain-id': ('ZROS_DOMAIN_ID', 'N', 'zros domain 0-232 (sets ZROS_DOMAIN_ID)'),
    '--connect': ('ZROS_CONNECT', 'EP', 'Zenoh endpoint to connect to, e.g. tcp/192.168.1.10:7447; '
                                        'repeatable (sets ZROS_CONNECT)'),
    '--listen': ('ZROS_LISTEN', 'EP', 'Zenoh endpoint to listen on, repeatable (sets ZROS_LISTEN)'),
    '--discovery': ('ZROS_DISCOVERY', 'MODE', 'localhost | subnet | off (sets ZROS_DISCOVERY)'),
    '--zenoh-config': ('ZROS_CONFIG', 'FILE', 'a Zenoh JSON5 config file (sets ZROS_CONFIG)'),
}


def add_session_options(parser) -> None:
    """Add the session options to an argparse parser (values land in `zros_<name>` attributes)."""
    group = parser.add_argument_group('session (see docs/multi-machine.md)')
    for option, (_, metavar, help_text) in SESSION_OPTIONS.items():
        repeat = option in ('--connect', '--listen')
        group.add_argument(option, dest='zros_' + option[2:].replace('-', '_'), metavar=metavar,
                           action='append' if repeat else 'store', default=None, help=help_text)


def apply_session_options(values: dict[str, object], env: os._Environ | dict | None = None) -> SessionSettings:
    """Export the given option values ({'--connect': [...], '--discovery': 'subnet', ...}; None
    for not given) as the environment variables the session reads, so that this process and
    every child it starts use them; then check them (ZrosError, one line, on a bad value)."""
    env = os.environ if env is None else env
    for option, value in values.items():
        if value is None or value == []:
            continue
        variable = SESSION_OPTIONS[option][0]
        if isinstance(value, (list, tuple)):
            value = ','.join(str(v) for v in value)
        value = str(value)
        if variable == 'ZROS_CONFIG' and value:
            value = os.path.abspath(value)   # children may run in another working directory
        env[variable] = value
    try:
        return settings_from_env(env)
    except ZrosError as exc:
        text = str(exc)
        for option, (variable, _, _) in SESSION_OPTIONS.items():
            if values.get(option) not in (None, []) and text.startswith(variable):
                text = f'{option} ({variable}){text[len(variable):]}'
                break
        raise ZrosError(text) from None


def split_session_options(argv: list[str]) -> tuple[dict[str, object], list[str]]:
    """Session options at the start of `argv` (`--connect EP` or `--connect=EP`), and the rest,
    untouched: how `zros run` reads its own options before the package and executable."""
    values: dict[str, object] = {}
    rest = list(argv)
    while rest and rest[0].startswith('--'):
        option, eq, inline = rest[0].partition('=')
        if option not in SESSION_OPTIONS:
            break
        if eq:
            value, rest = inline, rest[1:]
        elif len(rest) >= 2:
            value, rest = rest[1], rest[2:]
        else:
            raise ZrosError(f'{option} needs a value ({SESSION_OPTIONS[option][1]})')
        if option in ('--connect', '--listen'):
            values.setdefault(option, []).append(value)
        else:
            values[option] = value
    return values, rest


def hub_port_free(domain: int) -> bool:
    """Whether no process listens on the loopback hub port of `domain` (no hub is up): a cheap
    local check before asking Zenoh to bind it (a lost race is handled), and what tests and
    benchmarks pick a quiet domain by.

    SO_REUSEADDR as Zenoh's own listener sets it: connections of a hub that just exited linger
    in TIME_WAIT on the port, and without it the port would look taken for a minute.
    """
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind(('127.0.0.1', HUB_BASE_PORT + domain))
        except OSError:
            return False
    return True


def _default_listen(settings: SessionSettings) -> list[str]:
    """Where a session listens when neither ZROS_LISTEN nor the ZROS_CONFIG file says."""
    if settings.mode == 'client':
        return []
    if settings.mode == 'router':
        return [f'tcp/0.0.0.0:{HUB_BASE_PORT}']    # IPv4: tcp/[::] fails on hosts without IPv6
    if settings.uses_hub:
        return [f'{settings.link}/127.0.0.1:0']
    if settings.connect or settings.discovery == 'subnet':
        return [_ALL_IPV4]   # reachable by the peers this process meets through a router or multicast
    return [_LOOPBACK_ANY]


#: The Zenoh link lease on the loopback hub set-up (ms); Zenoh's default (10 s) elsewhere.
LOOPBACK_LEASE_MS = 60_000


def build_config(settings: SessionSettings, *, as_hub: bool, mesh: bool = True):
    """The Zenoh config for `settings`. `mesh=False` turns gossip off: the session links only to
    the endpoints it dials (the hub, a router), which is all a graph read needs, and opening and
    closing it costs one link instead of one per process of the system."""
    import zenoh
    loaded = _load_file(settings.config_file) if settings.config_file else None
    if loaded is not None:
        config = zenoh.Config.from_json5(str(loaded.config))   # a fresh copy: it is modified below
    else:
        config = zenoh.Config()
        config.insert_json5('mode', '"peer"')

    def put(key: str, value: object) -> None:
        config.insert_json5(key, json.dumps(value))

    def unset(key: str) -> bool:
        return loaded is None or loaded.get(key) is None

    put('scouting/multicast/enabled', settings.discovery == 'subnet')
    if settings.tls:
        # The enclave's file is a client's: a peer of the mTLS hub also listens, with the same
        # certificate (every enclave's names localhost and 127.0.0.1 and may serve TLS).
        put('mode', 'peer')
        for side in ('private_key', 'certificate'):
            if unset(f'transport/link/tls/listen_{side}'):
                put(f'transport/link/tls/listen_{side}', loaded.get(f'transport/link/tls/connect_{side}'))
    if not mesh:
        put('scouting/gossip/enabled', False)
    elif unset('scouting/gossip/enabled'):
        put('scouting/gossip/enabled', True)
    if settings.uses_hub:
        # One dialler per pair of processes. When both dial, the pair's session carries two
        # links, and a lease that expires on one side only (a process starved of CPU for 10 s
        # by a 100-node launch) can leave the pair split for good: the reconnection joins the
        # stale session and the declarations are never sent again (eclipse-zenoh/zenoh#2806).
        # On loopback anyone can dial anyone, so: every process dials the hub, the hub dials
        # nobody, and of two other processes the one with the greater id dials. (Across
        # machines both sides may dial, as one of them may not be reachable.)
        if unset('scouting/gossip/autoconnect_strategy'):
            put('scouting/gossip/autoconnect_strategy', {'peer': {'to_peer': 'greater-zid'}})
        if as_hub and unset('scouting/gossip/autoconnect'):
            put('scouting/gossip/autoconnect', {'peer': []})
        # A longer lease: every pair of processes is linked, and each link sends a keep-alive
        # every lease/4 when idle. With Zenoh's 10 s, 100 idle nodes spent 0.4 CPUs on 4,000
        # keep-alives a second. On loopback a process that exits or crashes closes its links
        # at once; the lease only bounds how long a frozen one (Ctrl-Z) stays in the graph.
        if unset('transport/link/tx/lease'):
            put('transport/link/tx/lease', LOOPBACK_LEASE_MS)
        # As long for a link's handshake. Zenoh cancels a handshake that outlasts the timeout
        # (10 s) wherever it is, even after the link has started sending but before it reads:
        # the link then stays up, half open, and no lease ends it. Under a 100-node start,
        # listeners never heard some talkers and the hub's graph lacked running nodes, for good.
        for key in ('transport/unicast/accept_timeout', 'transport/unicast/open_timeout'):
            if unset(key):
                put(key, LOOPBACK_LEASE_MS)
    put('timestamping/enabled', True)
    from zros.shm import zenoh_settings
    # the shared-memory pool (zros.shm). A file's values include Zenoh's defaults (shared memory
    # on), so ZROS_SHM_POOL_SIZE, when given, wins over the file as the other variables do: a
    # robot's client config must not bring shared memory back across namespaces of one host.
    shm_given = bool(os.environ.get('ZROS_SHM_POOL_SIZE', '').strip())
    for key, value in zenoh_settings().items():
        if shm_given or unset(key):
            put(key, value)
    # The loopback hub is re-dialled quickly: when its process exits, the next zros process takes
    # the port over, and a short-lived one (a CLI command) only waits ~0.3 s for peers to join.
    # A router across a network every 0.5 s at most: a robot whose Wi-Fi came back is in the
    # laptop's graph again within half a second of it (one dial a second more while it is away).
    retry_max_ms = 200 if settings.uses_hub else 500
    if unset('connect/retry/period_init_ms') and unset('connect/retry/period_max_ms'):
        put('connect/retry', {'period_init_ms': min(250, retry_max_ms // 2), 'period_max_ms': retry_max_ms,
                              'period_increase_factor': 2})
    listen = list(settings.listen)
    connect = list(settings.connect)
    if settings.uses_hub:
        if as_hub:
            listen = [settings.hub_endpoint] + listen
        else:
            connect = [settings.hub_endpoint] + connect
    if settings.mode == 'client':
        listen = []   # a client never listens
    elif not listen:
        listen = _default_listen(settings)
    if listen:
        put('listen/endpoints', listen)
    if connect or settings.tls:   # the enclave's file dials a router: the hub replaces it
        put('connect/endpoints', connect)
    return config


def open_session(settings: SessionSettings, *, mesh: bool = True, connect_wait: float | None = None):
    """Open the process's Zenoh session; returns (session, is_hub).

    A peer whose endpoints do not answer opens anyway and Zenoh keeps dialling in the background.
    Zenoh refuses to open a client without its router, so a client is retried here, with the same
    one-line warning, for `connect_wait` seconds (None: until the router answers).

    `mesh=False` (see build_config) applies to the loopback hub only, which serves the whole
    graph; a plain Zenoh router does not pass peers' tokens on, so there readers need the mesh."""
    import zenoh
    mesh = mesh or not settings.uses_hub
    if settings.uses_hub and hub_port_free(settings.domain_id):
        try:
            return zenoh.open(build_config(settings, as_hub=True, mesh=mesh)), True
        except zenoh.ZError:
            pass  # another process won the race for the hub port: join it instead
    if not mesh and not settings.tls:
        reader = _open_graph_reader(settings)
        if reader is not None:
            return reader, False
    if settings.mode == 'client':
        return _open_client(settings, mesh, connect_wait), False
    session = _open(build_config(settings, as_hub=False, mesh=mesh))
    if settings.uses_hub and not settings.listen and list(session.info.routers_zid()):
        session.close()
        if settings.tls:
            # The keystore's router (`zros router` with security on) holds the port: be its
            # client, as the enclave's file says, so that its access control sees every message.
            client = replace(settings, connect=(settings.hub_endpoint,), mode='client', tls=False)
            return _open_client(client, mesh, connect_wait), False
        # The hub port is held by a Zenoh router (`zros router` listens on 0.0.0.0:7447): join
        # it the way ZROS_CONNECT would, listening beyond loopback, so that the router's other
        # hosts can link to this process (a router does not forward between two peers).
        joined = SessionSettings(domain_id=settings.domain_id, connect=(settings.hub_endpoint,),
                                 discovery=settings.discovery, config_file=settings.config_file,
                                 mode=settings.mode, reasons=settings.reasons)
        session = _open(build_config(joined, as_hub=False, mesh=mesh))
    elif settings.connect and not list(session.info.routers_zid()) and not list(session.info.peers_zid()):
        # Zenoh keeps retrying in the background (so start order does not matter), but a
        # wrong address or a TLS-only router would otherwise look like an empty system.
        _warn_unreachable(settings)
    return session, False


def _open_graph_reader(settings: SessionSettings):
    """A session that only reads the graph (`mesh=False`): a Zenoh client of whatever holds the
    hub port, the loopback hub or a `zros router`, both of which answer the graph query; None
    when nothing answers there (the caller then opens a session its usual way).

    One link, nothing to listen on, and `open` returns once the link is up instead of waiting
    for the other side's declarations: a reader only queries, and a client sends every query to
    its router whatever it has declared. That wait is what made a command against a router slow:
    Zenoh gives a router up to 0.5 s to send them, on every open (measured in docs/benchmarks.md,
    "The robot and the laptop over a bad link")."""
    import zenoh
    config = build_config(replace(settings, connect=(settings.hub_endpoint,), mode='client'), as_hub=False,
                          mesh=False)
    config.insert_json5('open/return_conditions/declares', 'false')
    try:
        return zenoh.open(config)
    except zenoh.ZError:
        return None


def _open(config):
    import zenoh
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:
        raise ZrosError(f'cannot open the Zenoh session: {_zenoh_error_text(exc)}') from None


def _warn_unreachable(settings: SessionSettings) -> None:
    hint = ''
    if settings.reasons.get('config_file') == 'ROS_SECURITY_KEYSTORE':
        hint = (": it is the keystore's router; start it there (`zros router` with the same ROS_SECURITY_KEYSTORE "
                'and ROS_SECURITY_ENABLE=true), or, on one machine, leave ZROS_CONNECT and ZROS_DISCOVERY unset: '
                'secure nodes then need no router, they link to each other over TLS')
    print(f"zros: cannot reach {', '.join(settings.connect)} yet (retrying in the background){hint}",
          file=sys.stderr, flush=True)


def _sleep_unless_signalled(seconds: float) -> None:
    """Sleep, but end the wait for a router at once when SIGTERM (or a handled SIGINT) came in:
    there is no context yet for the signal to shut down."""
    import time
    from zros.signals import signal_received
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        if signal_received():
            raise ZrosError('stopped by a signal while waiting for the router')
        time.sleep(min(0.05, left))


def _open_client(settings: SessionSettings, mesh: bool, connect_wait: float | None):
    """Dial the router until it answers (every 0.25 s, backing off to 2 s) or `connect_wait` runs out."""
    import time
    import zenoh
    config = build_config(settings, as_hub=False, mesh=mesh)
    deadline = None if connect_wait is None else time.monotonic() + connect_wait
    delay = 0.25
    warned = False
    while True:
        try:
            return zenoh.open(config)
        except zenoh.ZError as exc:
            text = _zenoh_error_text(exc)
            if 'Unable to connect' not in text or (deadline is not None and time.monotonic() >= deadline):
                raise ZrosError(f'cannot open the Zenoh session: {text}') from None
        if not warned:
            _warn_unreachable(settings)
            warned = True
        pause = delay if deadline is None else min(delay, max(0.0, deadline - time.monotonic()))
        _sleep_unless_signalled(pause)
        delay = min(2.0, delay * 2)
        config = build_config(settings, as_hub=False, mesh=mesh)   # zenoh.open consumes it
