"""Which Zenoh session a zros process opens: one setting for one machine or many.

Zero set-up on one machine (DESIGN §5): the first zros process of a domain binds the domain's
hub port on loopback (7447 + domain id) and every later process connects to it; Zenoh's gossip
then links the processes to each other directly, so the hub is only a meeting point. When the
hub process exits, the others stay linked, and the next process to start takes the port over
(the others reconnect to it within a second). Nothing leaves loopback unless asked.

Environment (each also a `zros run` / `zros launch` option, see docs/multi-machine.md):
    ZROS_DOMAIN_ID   domain, isolates systems (default 0)
    ZROS_CONNECT     comma-separated endpoints to connect to (e.g. tcp/192.168.1.10:7447);
                     disables the loopback hub
    ZROS_LISTEN      comma-separated endpoints to listen on
    ZROS_DISCOVERY   localhost (default) | subnet (multicast scouting) | off
    ZROS_CONFIG      a Zenoh JSON5 config file, applied first; the settings above override it
"""
from __future__ import annotations

import json
import os
import socket
from dataclasses import dataclass, field

from zros.errors import ZrosError

__all__ = ['SessionSettings', 'settings_from_env', 'HUB_BASE_PORT', 'open_session']

HUB_BASE_PORT = 7447
DISCOVERY_MODES = ('localhost', 'subnet', 'off')


@dataclass(frozen=True)
class SessionSettings:
    domain_id: int = 0
    connect: tuple[str, ...] = ()
    listen: tuple[str, ...] = ()
    discovery: str = 'localhost'
    config_file: str | None = None
    reasons: dict[str, str] = field(default_factory=dict, compare=False)

    @property
    def hub_endpoint(self) -> str:
        return f'tcp/127.0.0.1:{HUB_BASE_PORT + self.domain_id}'

    @property
    def uses_hub(self) -> bool:
        return self.discovery == 'localhost' and not self.connect


def _split(value: str | None) -> tuple[str, ...]:
    return tuple(p.strip() for p in (value or '').split(',') if p.strip())


def settings_from_env(env: os._Environ | dict | None = None, *, domain_id: int | None = None) -> SessionSettings:
    env = os.environ if env is None else env
    reasons = {}
    if domain_id is None:
        raw = env.get('ZROS_DOMAIN_ID', env.get('ROS_DOMAIN_ID', '0')) or '0'
        try:
            domain_id = int(raw)
        except ValueError:
            raise ZrosError(f"ZROS_DOMAIN_ID must be an integer 0-232, got '{raw}'") from None
        reasons['domain_id'] = 'ZROS_DOMAIN_ID' if 'ZROS_DOMAIN_ID' in env else 'default'
    if not 0 <= domain_id <= 232:
        raise ZrosError(f'domain id must be within 0-232, got {domain_id}')
    discovery = (env.get('ZROS_DISCOVERY') or 'localhost').strip().lower()
    if discovery not in DISCOVERY_MODES:
        raise ZrosError(f"ZROS_DISCOVERY must be one of {', '.join(DISCOVERY_MODES)}, got '{discovery}'")
    return SessionSettings(
        domain_id=domain_id,
        connect=_split(env.get('ZROS_CONNECT')),
        listen=_split(env.get('ZROS_LISTEN')),
        discovery=discovery,
        config_file=env.get('ZROS_CONFIG') or None,
        reasons=reasons,
    )


def _hub_port_free(port: int) -> bool:
    """A cheap local check before asking Zenoh to bind the hub port (a lost race is handled).

    SO_REUSEADDR as Zenoh's own listener sets it: connections of a hub that just exited linger
    in TIME_WAIT on the port, and without it the port would look taken for a minute.
    """
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind(('127.0.0.1', port))
        except OSError:
            return False
    return True


def build_config(settings: SessionSettings, *, as_hub: bool):
    import zenoh
    if settings.config_file:
        try:
            config = zenoh.Config.from_file(settings.config_file)
        except Exception as exc:  # noqa: BLE001 - zenoh raises its own error type with the reason
            raise ZrosError(f"cannot load ZROS_CONFIG '{settings.config_file}': {exc}") from None
    else:
        config = zenoh.Config()
        config.insert_json5('mode', '"peer"')

    def put(key: str, value: object) -> None:
        config.insert_json5(key, json.dumps(value))

    put('scouting/multicast/enabled', settings.discovery == 'subnet')
    put('scouting/gossip/enabled', True)
    put('timestamping/enabled', True)
    # The loopback hub is re-dialled quickly: when its process exits, the next zros process takes
    # the port over, and a short-lived one (a CLI command) only waits ~0.3 s for peers to join.
    retry_max_ms = 200 if settings.uses_hub else 1000
    put('connect/retry', {'period_init_ms': min(250, retry_max_ms // 2), 'period_max_ms': retry_max_ms,
                          'period_increase_factor': 2})
    listen = list(settings.listen)
    connect = list(settings.connect)
    if settings.uses_hub:
        if as_hub:
            listen = [settings.hub_endpoint] + listen
        else:
            connect = [settings.hub_endpoint] + connect
    if not listen and not settings.config_file:
        listen = ['tcp/127.0.0.1:0'] if settings.discovery != 'subnet' else ['tcp/0.0.0.0:0']
    if listen:
        put('listen/endpoints', listen)
    if connect:
        put('connect/endpoints', connect)
    return config


def open_session(settings: SessionSettings):
    """Open the process's Zenoh session; returns (session, is_hub)."""
    import zenoh
    if settings.uses_hub and _hub_port_free(HUB_BASE_PORT + settings.domain_id):
        try:
            return zenoh.open(build_config(settings, as_hub=True)), True
        except zenoh.ZError:
            pass  # another process won the race for the hub port: join it instead
    try:
        return zenoh.open(build_config(settings, as_hub=False)), False
    except zenoh.ZError as exc:
        raise ZrosError(f'cannot open the Zenoh session: {exc}') from None
