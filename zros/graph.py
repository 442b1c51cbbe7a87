"""The ROS graph, read from Zenoh liveliness tokens: no daemon, no polling.

Each node and each of its entities declares one token (format below, protocol v1). A token
vanishes when its entity is destroyed, its process exits or its link dies, so the graph tracks
crashes within Zenoh's link-failure detection (immediate on loopback).

    @zros/v1/<domain>/<zid>/<node_id>/<entity_id>/NN/<ns>/<node>
    @zros/v1/<domain>/<zid>/<node_id>/<entity_id>/<KIND>/<ns>/<node>/<name>/<type>/<hash>/<qos>

KIND is MP (publisher), MS (subscription), SS (service server), SC (service client),
AS (action server), AC (action client). <ns>, <name> and <type> are mangled by zros.keys.mangle.
"""
from __future__ import annotations

import threading
from typing import Callable, Iterable, NamedTuple

from zros.keys import liveliness_prefix, mangle, unmangle

__all__ = [
    'Entity', 'EntityKind', 'entity_token', 'parse_token', 'Graph', 'fetch_entities',
    'node_names_and_namespaces', 'names_and_types', 'endpoints',
]


class EntityKind:
    NODE = 'NN'
    PUBLISHER = 'MP'
    SUBSCRIPTION = 'MS'
    SERVICE = 'SS'
    CLIENT = 'SC'
    ACTION_SERVER = 'AS'
    ACTION_CLIENT = 'AC'


class Entity(NamedTuple):
    kind: str
    zid: str
    node_id: int
    entity_id: int
    namespace: str
    node_name: str
    name: str = ''          # fully qualified topic / service / action name
    type: str = ''          # 'pkg/msg/Name'
    type_hash: str = ''
    qos: str = ''           # QoSProfile.to_token()

    @property
    def node_fqn(self) -> str:
        return ('' if self.namespace == '/' else self.namespace) + '/' + self.node_name

    @property
    def node_key(self) -> tuple[str, int]:
        """Identifies one node instance (two nodes may share a name)."""
        return (self.zid, self.node_id)


def entity_token(domain: int, entity: Entity) -> str:
    head = (f'{liveliness_prefix(domain)}/{entity.zid}/{entity.node_id}/{entity.entity_id}/'
            f'{entity.kind}/{mangle(entity.namespace.rstrip("/"))}/{entity.node_name}')
    if entity.kind == EntityKind.NODE:
        return head
    return f'{head}/{mangle(entity.name)}/{mangle(entity.type)}/{entity.type_hash or "%"}/{entity.qos or "%"}'


def parse_token(key: str) -> Entity | None:
    """Entity for a token key; None for anything that is not a well-formed v1 token."""
    parts = str(key).split('/')
    try:
        if parts[0] != '@zros' or parts[1] != 'v1':
            return None
        zid, node_id, entity_id, kind, ns, node = parts[3], int(parts[4]), int(parts[5]), parts[6], parts[7], parts[8]
        namespace = unmangle(ns) or '/'
        if kind == EntityKind.NODE:
            return Entity(kind, zid, node_id, entity_id, namespace, node) if len(parts) == 9 else None
        if len(parts) != 13:
            return None
        type_hash = '' if parts[11] == '%' else parts[11]
        qos = '' if parts[12] == '%' else parts[12]
        return Entity(kind, zid, node_id, entity_id, namespace, node,
                      unmangle(parts[9]), unmangle(parts[10]), type_hash, qos)
    except (IndexError, ValueError):
        return None


def fetch_entities(session, domain: int, timeout: float = 1.0) -> list[Entity]:
    """One-shot read of the whole graph (what the CLI uses: no subscriber to set up)."""
    found = []
    for reply in session.liveliness().get(f'{liveliness_prefix(domain)}/**', timeout=timeout):
        ok = reply.ok
        if ok is not None:
            entity = parse_token(str(ok.key_expr))
            if entity is not None:
                found.append(entity)
    return found


class Graph:
    """A live copy of the graph kept by a liveliness subscriber; one per context.

    `wait_for(predicate, timeout)` blocks until the predicate holds over the current entities,
    which is how `wait_for_service` and friends avoid polling the network.
    """

    def __init__(self, session, domain: int) -> None:
        self._session = session
        self._domain = domain
        self._entities: dict[str, Entity] = {}
        self._changed = threading.Condition()
        self._listeners: list[Callable[[], None]] = []
        self._subscriber = None
        self._started = threading.Event()
        self._start_lock = threading.Lock()

    def _ensure_started(self) -> None:
        if self._started.is_set():
            return
        with self._start_lock:
            if self._started.is_set():
                return
            # Seed from a query first: the history of a liveliness subscriber arrives
            # asynchronously, and callers expect the graph to be complete on return.
            for entity in fetch_entities(self._session, self._domain):
                self._entities[entity_token(self._domain, entity)] = entity
            self._subscriber = self._session.liveliness().declare_subscriber(
                f'{liveliness_prefix(self._domain)}/**', self._on_sample, history=True)
            self._started.set()

    def _on_sample(self, sample) -> None:
        import zenoh
        key = str(sample.key_expr)
        with self._changed:
            if sample.kind == zenoh.SampleKind.DELETE:
                self._entities.pop(key, None)
            else:
                entity = parse_token(key)
                if entity is None:
                    return
                self._entities[key] = entity
            self._changed.notify_all()
            listeners = list(self._listeners)
        for listener in listeners:
            listener()

    def add_listener(self, listener: Callable[[], None]) -> None:
        """Called (on a Zenoh thread) after every change; must be quick and thread-safe."""
        with self._changed:
            self._listeners.append(listener)

    def remove_listener(self, listener: Callable[[], None]) -> None:
        with self._changed:
            if listener in self._listeners:
                self._listeners.remove(listener)

    def entities(self) -> list[Entity]:
        self._ensure_started()
        with self._changed:
            return list(self._entities.values())

    def wait_for(self, predicate: Callable[[list[Entity]], bool], timeout: float | None) -> bool:
        self._ensure_started()
        with self._changed:
            return self._changed.wait_for(lambda: predicate(list(self._entities.values())), timeout)

    def close(self) -> None:
        if self._subscriber is not None:
            self._subscriber.undeclare()
            self._subscriber = None
        with self._changed:
            self._changed.notify_all()


def node_names_and_namespaces(entities: Iterable[Entity]) -> list[tuple[str, str]]:
    nodes = {(e.node_key, e.node_name, e.namespace) for e in entities if e.kind == EntityKind.NODE}
    return sorted((name, ns) for _, name, ns in nodes)


def names_and_types(entities: Iterable[Entity], kinds: tuple[str, ...]) -> list[tuple[str, list[str]]]:
    """[(name, [types...])] over entities of the given kinds, sorted by name."""
    table: dict[str, set[str]] = {}
    for e in entities:
        if e.kind in kinds:
            table.setdefault(e.name, set()).add(e.type)
    return [(name, sorted(types)) for name, types in sorted(table.items())]


def endpoints(entities: Iterable[Entity], kind: str, name: str) -> list[Entity]:
    return [e for e in entities if e.kind == kind and e.name == name]
