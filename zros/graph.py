"""The ROS graph, read from Zenoh liveliness tokens: no daemon, no polling.

Each node and each of its entities declares one token (format below, protocol v1). A token
vanishes when its entity is destroyed, its process exits or its link dies, so the graph tracks
crashes within Zenoh's link-failure detection (immediate on loopback).

A process that has just opened its session has not yet been linked to every peer (Zenoh's
gossip takes 0.1-0.5 s), so a plain liveliness query could miss most of the graph. The hub
process therefore keeps the whole graph (every process connects to it) and serves it on the
queryable `@zros/v1/<domain>/graph`; readers ask it and retry until it answers. Without a hub
(explicit ZROS_CONNECT set-ups) readers collect tokens with a liveliness subscriber until they
stop arriving.

    @zros/v1/<domain>/<zid>/<node_id>/<entity_id>/NN/<ns>/<node>
    @zros/v1/<domain>/<zid>/<node_id>/<entity_id>/<KIND>/<ns>/<node>/<name>/<type>/<hash>/<qos>

KIND is MP (publisher), MS (subscription), SS (service server), SC (service client),
AS (action server), AC (action client). <ns>, <name> and <type> are mangled by zros.keys.mangle.
"""
from __future__ import annotations

import threading
import time
from typing import Any, Callable, Iterable, NamedTuple

from zros.keys import liveliness_prefix, mangle, unmangle

__all__ = [
    'Entity', 'EntityKind', 'EntityList', 'entity_token', 'parse_token', 'Graph', 'fetch_entities', 'GraphService',
    'StatsService', 'fetch_subscription_stats',
    'node_names_and_namespaces', 'names_and_types', 'endpoints', 'undeclare_quietly',
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


# Shortest interval between two calls of the graph's listeners.
_LISTENER_INTERVAL_S = 0.05


def undeclare_quietly(declaration: Any) -> None:
    """Undeclare a Zenoh declaration (None: nothing to do); errors of a session that is
    already closing are ignored."""
    if declaration is None:
        return
    try:
        declaration.undeclare()
    except Exception:  # noqa: BLE001 - the session may already be closing
        pass


def _graph_key(domain: int) -> str:
    return f'{liveliness_prefix(domain)}/graph'


def _parse_all(keys: Iterable[str]) -> list[Entity]:
    return [e for e in (parse_token(k) for k in keys) if e is not None]


class EntityList(list):
    """Entities of a one-shot graph read; `complete` is False when the read ran out of time
    before it had a whole answer (the hub did not reply, or tokens were still arriving)."""

    complete = True


def _replies(query: Callable[[Any], Any], deadline: float) -> list:
    """The OK replies of a Zenoh query started by `query(handler)`, collected by a callback
    until the query is finalized or `deadline` (monotonic) passes, whichever comes first.

    A FIFO receiver would block Zenoh on its 257th reply while this thread has not started to
    drain it (a liveliness query is answered from the local table, on the calling thread), which
    froze graph reads with 50 nodes up."""
    import zenoh
    replies: list = []
    done = threading.Event()
    query(zenoh.handlers.Callback(lambda reply: replies.append(reply), done.set))
    done.wait(max(0.0, deadline - time.monotonic()))
    return [reply.ok for reply in list(replies) if reply.ok is not None]


def fetch_entities(session, domain: int, timeout: float = 1.0, *, is_hub: bool = False,
                   hub_wait: float | None = None) -> EntityList:
    """One-shot read of the whole graph (what the CLI uses), always answered within `timeout`.

    The hub (or a `zros router`) is asked first, for up to `hub_wait` seconds (default: all of
    `timeout`); set-ups without one (a plain Zenoh router) pass a short wait and fall back to
    collecting tokens. A read cut short by the deadline returns what it has, marked incomplete."""
    import msgpack
    started = time.monotonic()
    deadline = started + timeout
    if not is_hub:
        ask_until = started + (timeout if hub_wait is None else min(hub_wait, timeout))
        while time.monotonic() < ask_until:
            wait = max(0.05, min(0.5, deadline - time.monotonic()))
            answers = _replies(lambda handler: session.get(_graph_key(domain), handler, timeout=wait),
                               time.monotonic() + wait + 0.1)
            if answers:
                keys = set(msgpack.unpackb(answers[0].payload.to_bytes()))
                # Tokens the hub has not seen yet (declared a moment ago) are in the local table.
                local = min(0.2, max(0.05, deadline - time.monotonic()))
                keys.update(str(sample.key_expr) for sample in _replies(
                    lambda handler: session.liveliness().get(f'{liveliness_prefix(domain)}/**', handler,
                                                             timeout=local),
                    time.monotonic() + local + 0.1))
                return EntityList(_parse_all(keys))
            time.sleep(0.01)  # the hub's queryable is not known to this fresh session yet
    return _collect(session, domain, max(0.3, deadline - time.monotonic()), wait_for_peers=is_hub,
                    hub_missing=not is_hub and (hub_wait is None or hub_wait >= timeout))


def _collect(session, domain: int, limit: float, *, wait_for_peers: bool, hub_missing: bool) -> EntityList:
    """Tokens from a liveliness subscriber, until none has arrived for a moment (complete) or
    `limit` runs out (incomplete; so is any read that expected a hub and got none)."""
    keys: dict[str, bool] = {}
    last_change = [time.monotonic()]

    def on_sample(sample) -> None:
        import zenoh
        key = str(sample.key_expr)
        if sample.kind == zenoh.SampleKind.DELETE:
            keys.pop(key, None)
        else:
            keys[key] = True
        last_change[0] = time.monotonic()
    subscriber = session.liveliness().declare_subscriber(f'{liveliness_prefix(domain)}/**', on_sample, history=True)
    settled = False
    try:
        started = time.monotonic()
        end = started + limit
        # A hub that nobody has connected to yet may have peers reconnecting from a hub that
        # just exited; give them a moment, then stop as soon as the tokens stop coming.
        quiet = 0.1
        had_peers = False
        while time.monotonic() < end:
            time.sleep(0.02)
            now = time.monotonic()
            if wait_for_peers and not had_peers:
                if list(session.info.peers_zid()):
                    had_peers = True
                    last_change[0] = max(last_change[0], now)  # their tokens are on the way
                elif now - started < 0.3:
                    continue
            if now - last_change[0] >= quiet and now - started >= quiet:
                settled = True
                break
    finally:
        subscriber.undeclare()
    entities = EntityList(_parse_all(list(keys)))
    entities.complete = settled and not hub_missing
    return entities


class StatsService:
    """Run by every process: the delivery counters of its subscriptions, for `zros topic info -v`
    (a full queue drops and a gap loses messages visibly, never silently: docs/architecture.md §6)."""

    def __init__(self, session, domain: int, zid: str, subscriptions: Callable[[], Iterable]) -> None:
        self._subscriptions = subscriptions
        self._key = f'{liveliness_prefix(domain)}/stats/{zid}'
        self._queryable = session.declare_queryable(self._key, self._on_query, complete=True)

    def _on_query(self, query) -> None:
        import msgpack
        try:
            table = {f'{sub.graph_entity.node_id}.{sub.graph_entity.entity_id}':
                     [sub.received, sub.dropped, sub.lost, sub.rejected] for sub in self._subscriptions()}
            query.reply(self._key, msgpack.packb(table))  # its own key: readers take the zid from it
        finally:
            query.drop()

    def close(self, undeclare: Callable[[Any], None] | None = None) -> None:
        (undeclare or undeclare_quietly)(self._queryable)


def fetch_subscription_stats(session, domain: int, timeout: float = 1.0) -> dict[tuple[str, int, int], list[int]]:
    """(zid, node_id, entity_id) -> [received, dropped, lost, rejected] for every subscription."""
    import msgpack
    stats = {}
    key = f'{liveliness_prefix(domain)}/stats/*'
    for sample in _replies(lambda handler: session.get(key, handler, timeout=timeout),
                           time.monotonic() + timeout + 0.1):
        zid = str(sample.key_expr).rsplit('/', 1)[-1]
        for entry, counters in msgpack.unpackb(sample.payload.to_bytes()).items():
            node_id, entity_id = entry.split('.')
            stats[(zid, int(node_id), int(entity_id))] = counters
    return stats


class GraphService:
    """Run by the hub process: serves its complete copy of the graph to fresh readers."""

    def __init__(self, session, domain: int, graph: 'Graph') -> None:
        self._graph = graph
        self._queryable = session.declare_queryable(_graph_key(domain), self._on_query, complete=True)

    def _on_query(self, query) -> None:
        import msgpack
        try:
            query.reply(query.key_expr, msgpack.packb(self._graph.token_keys()))
        finally:
            query.drop()

    def close(self, undeclare: Callable[[Any], None] | None = None) -> None:
        (undeclare or undeclare_quietly)(self._queryable)


class Graph:
    """A live copy of the graph kept by a liveliness subscriber; one per context.

    `wait_for(predicate, timeout)` blocks until the predicate holds over the current entities,
    which is how `wait_for_service` and friends avoid polling the network.
    """

    def __init__(self, session, domain: int, *, is_hub: bool = False, hub_wait: float | None = None) -> None:
        self._session = session
        self._domain = domain
        self._is_hub = is_hub
        self._hub_wait = hub_wait
        self._entities: dict[str, Entity] = {}
        self._changed = threading.Condition()
        self._listeners: list[Callable[[], None]] = []
        self._subscriber = None
        self._started = threading.Event()
        self._start_lock = threading.Lock()
        self._closed = False
        self._notify_pending = False
        self._changed_event = threading.Event()
        self._listener_thread: threading.Thread | None = None

    def _ensure_started(self) -> None:
        if self._started.is_set():
            return
        with self._start_lock:
            if self._started.is_set():
                return
            self._subscriber = self._session.liveliness().declare_subscriber(
                f'{liveliness_prefix(self._domain)}/**', self._on_sample, history=True)
            # The subscriber's history arrives as links form; callers expect a complete graph
            # on return, so seed it from the hub (or a settled collection) as well.
            if not self._is_hub:
                seeded = fetch_entities(self._session, self._domain, hub_wait=self._hub_wait)
                with self._changed:
                    for entity in seeded:
                        self._entities.setdefault(entity_token(self._domain, entity), entity)
            self._started.set()

    def _on_sample(self, sample) -> None:
        import zenoh
        if self._closed:
            return  # samples still queued for this callback when the graph was closed
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
            if self._listeners and not self._notify_pending:
                self._notify_pending = True
                self._changed_event.set()

    def _notify_listeners(self) -> None:
        """Listener thread: one call per listener for a burst of changes, at most every
        `_LISTENER_INTERVAL_S`. When 100 nodes start or stop, each process sees a thousand token
        changes; a listener that compares QoS across the graph must not run a thousand times."""
        while True:
            self._changed_event.wait()
            if self._closed:
                return
            time.sleep(_LISTENER_INTERVAL_S)   # let the rest of the burst arrive
            with self._changed:
                self._changed_event.clear()
                self._notify_pending = False
                listeners = list(self._listeners)
            for listener in listeners:
                try:
                    listener()
                except Exception:  # noqa: BLE001 - one failing listener must not stop the others
                    pass

    def add_listener(self, listener: Callable[[], None]) -> None:
        """Called on the graph's listener thread after changes (once per burst); must be quick
        and thread-safe."""
        with self._changed:
            self._listeners.append(listener)
            if self._listener_thread is None:
                self._listener_thread = threading.Thread(target=self._notify_listeners, name='zros-graph',
                                                         daemon=True)
                self._listener_thread.start()

    def remove_listener(self, listener: Callable[[], None]) -> None:
        with self._changed:
            if listener in self._listeners:
                self._listeners.remove(listener)

    def start(self) -> None:
        self._ensure_started()

    def add_local(self, entity: Entity) -> None:
        """Record an entity of this process at once (Zenoh reports it a moment later), so that
        `count_subscribers()` right after `create_subscription()` counts it, as in rclpy."""
        with self._changed:
            self._entities[entity_token(self._domain, entity)] = entity
            self._changed.notify_all()

    def remove_local(self, entity: Entity) -> None:
        with self._changed:
            self._entities.pop(entity_token(self._domain, entity), None)
            self._changed.notify_all()

    def token_keys(self) -> list[str]:
        with self._changed:
            return list(self._entities)

    def entities(self) -> list[Entity]:
        self._ensure_started()
        with self._changed:
            return list(self._entities.values())

    def wait_for(self, predicate: Callable[[list[Entity]], bool], timeout: float | None) -> bool:
        self._ensure_started()
        with self._changed:
            return self._changed.wait_for(lambda: predicate(list(self._entities.values())), timeout)

    def close(self, undeclare: Callable[[Any], None] | None = None) -> None:
        """Stop following the graph; `undeclare` releases the subscriber (the context's, which
        after a signal leaves that to the session's close)."""
        self._closed = True
        self._changed_event.set()
        if self._subscriber is not None:
            (undeclare or undeclare_quietly)(self._subscriber)
            self._subscriber = None
        with self._changed:
            self._listeners.clear()
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
