"""QoS events, as rclpy.event_handler: callbacks for what happens to a publisher or a
subscription besides its messages, each firing for a real cause.

- deadline: a QoS `deadline` period passed without a message (subscription: requested;
  publisher: offered). Counting starts with the first message, as in DDS.
- liveliness: a subscription's matched publishers appear or vanish (Zenoh liveliness tokens
  vanish when a publisher is destroyed, its process dies or its link fails); a publisher with
  MANUAL_BY_TOPIC liveliness and a lease that neither publishes nor calls
  `assert_liveliness()` within the lease has lost its liveliness.
- incompatible_qos: an endpoint on the topic breaks a request/offer rule (zros.qos).
- message_lost: gaps in a publisher's sequence numbers (what `subscription.lost` counts).
- matched: endpoints of the other side (same topic, same type) appear or vanish.
- incompatible_type: an endpoint of the other side has another type or definition.

The payloads are rmw's status structs (NamedTuples with the same fields): counts are totals,
`*_change` fields what changed since the callback last ran. Callbacks run on the executor in
the entity's callback group, like rclpy's event handlers.
"""
from __future__ import annotations

import enum
import heapq
import itertools
import threading
import time
from typing import TYPE_CHECKING, Any, Callable, NamedTuple

from zros.graph import Entity, EntityKind
from zros.qos import LivelinessPolicy, QoSPolicyKind, qos_policy_name_from_kind

if TYPE_CHECKING:
    from zros.callback_groups import CallbackGroup

__all__ = [
    'EventHandler', 'PublisherEventCallbacks', 'SubscriptionEventCallbacks', 'QoSPublisherEventType',
    'QoSSubscriptionEventType', 'QoSRequestedDeadlineMissedInfo', 'QoSOfferedDeadlineMissedInfo',
    'QoSLivelinessChangedInfo', 'QoSLivelinessLostInfo', 'QoSMessageLostInfo', 'QoSRequestedIncompatibleQoSInfo',
    'QoSOfferedIncompatibleQoSInfo', 'QoSSubscriptionMatchedInfo', 'QoSPublisherMatchedInfo',
    'IncompatibleTypeInfo', 'UnsupportedEventTypeError', 'attach_event_callbacks', 'report_incompatible_qos',
    'report_incompatible_type', 'same_type', 'graph_changed',
]


class UnsupportedEventTypeError(Exception):
    """Kept for rclpy compatibility: zros supports every event type."""


class QoSPublisherEventType(enum.IntEnum):
    RCL_PUBLISHER_OFFERED_DEADLINE_MISSED = 0
    RCL_PUBLISHER_LIVELINESS_LOST = 1
    RCL_PUBLISHER_OFFERED_INCOMPATIBLE_QOS = 2
    RCL_PUBLISHER_INCOMPATIBLE_TYPE = 3
    RCL_PUBLISHER_MATCHED = 4


class QoSSubscriptionEventType(enum.IntEnum):
    RCL_SUBSCRIPTION_REQUESTED_DEADLINE_MISSED = 0
    RCL_SUBSCRIPTION_LIVELINESS_CHANGED = 1
    RCL_SUBSCRIPTION_REQUESTED_INCOMPATIBLE_QOS = 2
    RCL_SUBSCRIPTION_MESSAGE_LOST = 3
    RCL_SUBSCRIPTION_INCOMPATIBLE_TYPE = 4
    RCL_SUBSCRIPTION_MATCHED = 5


class QoSRequestedDeadlineMissedInfo(NamedTuple):
    total_count: int
    total_count_change: int


class QoSOfferedDeadlineMissedInfo(NamedTuple):
    total_count: int
    total_count_change: int


class QoSLivelinessChangedInfo(NamedTuple):
    alive_count: int
    not_alive_count: int
    alive_count_change: int
    not_alive_count_change: int


class QoSLivelinessLostInfo(NamedTuple):
    total_count: int
    total_count_change: int


class QoSMessageLostInfo(NamedTuple):
    total_count: int
    total_count_change: int


class QoSRequestedIncompatibleQoSInfo(NamedTuple):
    total_count: int
    total_count_change: int
    last_policy_kind: QoSPolicyKind


QoSOfferedIncompatibleQoSInfo = QoSRequestedIncompatibleQoSInfo


class QoSSubscriptionMatchedInfo(NamedTuple):
    total_count: int
    total_count_change: int
    current_count: int
    current_count_change: int


QoSPublisherMatchedInfo = QoSSubscriptionMatchedInfo


class IncompatibleTypeInfo(NamedTuple):
    total_count: int
    total_count_change: int


def _merge(pending: NamedTuple | None, new: NamedTuple) -> NamedTuple:
    """Two events before the callback ran: the newer totals, the summed changes."""
    if pending is None:
        return new
    return new._replace(**{f: getattr(pending, f) + getattr(new, f) for f in new._fields if f.endswith('_change')})


class EventHandler:
    """One callback for one event type of one publisher or subscription (rclpy's Waitable).
    Made by the *EventCallbacks containers; the executor runs it in `callback_group`."""

    def __init__(self, *, callback_group: 'CallbackGroup', callback: Callable[[Any], Any], event_type: enum.IntEnum,
                 parent: Any) -> None:
        self.callback_group = callback_group
        self.callback = callback
        self.event_type = event_type
        self._parent = parent
        self._lock = threading.Lock()
        self._pending: NamedTuple | None = None
        self._scheduled = False
        self._destroyed = False

    def _fire(self, info: NamedTuple) -> None:
        """Any thread: queue `info` for the callback (merged with one still waiting)."""
        with self._lock:
            if self._destroyed:
                return
            self._pending = _merge(self._pending, info)
            if self._scheduled:
                return
            self._scheduled = True
        executor = self._parent._node._executor
        if executor is not None:
            executor._enqueue(self)

    def _has_work(self) -> bool:
        return self._pending is not None

    def _execute(self) -> None:
        with self._lock:
            info, self._pending, self._scheduled = self._pending, None, False
        if info is not None and not self._destroyed:
            self.callback(info)

    def destroy(self) -> None:
        with self._lock:
            self._destroyed = True
            self._pending = None


class _Callbacks:
    """What the two containers share: the user's callbacks by event name."""

    _EVENTS: dict[str, enum.IntEnum] = {}

    def __init__(self, use_default_callbacks: bool, **callbacks: Callable | None) -> None:
        for name, callback in callbacks.items():
            setattr(self, name, callback)
        self.use_default_callbacks = use_default_callbacks

    def create_event_handlers(self, callback_group: 'CallbackGroup', parent: Any, topic_name: str) -> list[EventHandler]:
        """One handler per callback given, plus, unless `use_default_callbacks` is False, the
        default warnings of incompatible QoS and of incompatible types (as rclpy)."""
        handlers = []
        for name, event_type in self._EVENTS.items():
            callback = getattr(self, name)
            if callback is None and self.use_default_callbacks and name in _DEFAULT_CALLBACKS:
                callback = _DEFAULT_CALLBACKS[name](parent, topic_name)
            if callback is not None:
                handlers.append(EventHandler(callback_group=callback_group, callback=callback,
                                             event_type=event_type, parent=parent))
        return handlers


class SubscriptionEventCallbacks(_Callbacks):
    """The event callbacks of a subscription (`create_subscription(..., event_callbacks=)`)."""

    _EVENTS = {'deadline': QoSSubscriptionEventType.RCL_SUBSCRIPTION_REQUESTED_DEADLINE_MISSED,
               'incompatible_qos': QoSSubscriptionEventType.RCL_SUBSCRIPTION_REQUESTED_INCOMPATIBLE_QOS,
               'liveliness': QoSSubscriptionEventType.RCL_SUBSCRIPTION_LIVELINESS_CHANGED,
               'message_lost': QoSSubscriptionEventType.RCL_SUBSCRIPTION_MESSAGE_LOST,
               'incompatible_type': QoSSubscriptionEventType.RCL_SUBSCRIPTION_INCOMPATIBLE_TYPE,
               'matched': QoSSubscriptionEventType.RCL_SUBSCRIPTION_MATCHED}

    def __init__(self, *, deadline: Callable | None = None, incompatible_qos: Callable | None = None,
                 liveliness: Callable | None = None, message_lost: Callable | None = None,
                 incompatible_type: Callable | None = None, matched: Callable | None = None,
                 use_default_callbacks: bool = True) -> None:
        super().__init__(use_default_callbacks, deadline=deadline, incompatible_qos=incompatible_qos,
                         liveliness=liveliness, message_lost=message_lost, incompatible_type=incompatible_type,
                         matched=matched)


class PublisherEventCallbacks(_Callbacks):
    """The event callbacks of a publisher (`create_publisher(..., event_callbacks=)`)."""

    _EVENTS = {'deadline': QoSPublisherEventType.RCL_PUBLISHER_OFFERED_DEADLINE_MISSED,
               'liveliness': QoSPublisherEventType.RCL_PUBLISHER_LIVELINESS_LOST,
               'incompatible_qos': QoSPublisherEventType.RCL_PUBLISHER_OFFERED_INCOMPATIBLE_QOS,
               'incompatible_type': QoSPublisherEventType.RCL_PUBLISHER_INCOMPATIBLE_TYPE,
               'matched': QoSPublisherEventType.RCL_PUBLISHER_MATCHED}

    def __init__(self, *, deadline: Callable | None = None, liveliness: Callable | None = None,
                 incompatible_qos: Callable | None = None, incompatible_type: Callable | None = None,
                 matched: Callable | None = None, use_default_callbacks: bool = True) -> None:
        super().__init__(use_default_callbacks, deadline=deadline, liveliness=liveliness,
                         incompatible_qos=incompatible_qos, incompatible_type=incompatible_type, matched=matched)


def _default_incompatible_qos(parent: Any, topic: str) -> Callable[[QoSRequestedIncompatibleQoSInfo], None]:
    def warn(info: QoSRequestedIncompatibleQoSInfo) -> None:
        other = getattr(getattr(parent, '_event_tracker', None), 'last_incompatible', None)
        parent._node.get_logger().warn(_incompatible_text(parent, topic, info.last_policy_kind, other))
    return warn


def _default_incompatible_type(parent: Any, topic: str) -> Callable[[IncompatibleTypeInfo], None]:
    def warn(info: IncompatibleTypeInfo) -> None:
        # Samples of another type do not decode as this one's and are dropped.
        parent._node.get_logger().warn(f"Incompatible type on topic '{topic}', no messages will be sent to it.")
    return warn


# event name -> the factory of the callback a handler gets when the user gives none
_DEFAULT_CALLBACKS = {'incompatible_qos': _default_incompatible_qos, 'incompatible_type': _default_incompatible_type}


def _incompatible_text(parent: Any, topic: str, policy: QoSPolicyKind, other: Entity | None) -> str:
    who = f' ({"publisher" if _is_subscription(parent) else "subscription"} {other.node_fqn}; ' if other else ' ('
    if _is_subscription(parent):
        return (f"New publisher discovered on topic '{topic}', offering incompatible QoS. Last incompatible "
                f'policy: {qos_policy_name_from_kind(policy)}{who}ROS 2 would receive nothing from it, '
                'zros still delivers)')
    return (f"New subscription discovered on topic '{topic}', requesting incompatible QoS. Last incompatible "
            f'policy: {qos_policy_name_from_kind(policy)}{who}ROS 2 would deliver nothing to it, zros still does)')


def _is_subscription(entity: Any) -> bool:
    return entity.graph_entity.kind == EntityKind.SUBSCRIPTION


# -- what makes the events fire -------------------------------------------------------------------
class _Watchdog:
    """One thread for the whole process that wakes trackers when a deadline or lease falls due
    (one heap entry per tracker and kind; idle, it waits without polling)."""

    def __init__(self) -> None:
        self._heap: list[tuple[float, int, '_Tracker', str]] = []
        self._order = itertools.count()
        self._changed = threading.Condition()
        self._thread: threading.Thread | None = None

    def schedule(self, due: float, tracker: '_Tracker', kind: str) -> None:
        with self._changed:
            heapq.heappush(self._heap, (due, next(self._order), tracker, kind))
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name='zros-qos-events', daemon=True)
                self._thread.start()
            self._changed.notify()

    def _run(self) -> None:
        while True:
            with self._changed:
                while not self._heap or self._heap[0][0] > time.monotonic():
                    self._changed.wait(None if not self._heap else self._heap[0][0] - time.monotonic())
                due, _, tracker, kind = heapq.heappop(self._heap)
            try:
                tracker._due(kind, due)
            except Exception:  # noqa: BLE001 - a failing tracker must not stop the others
                pass


_watchdog = _Watchdog()


class _Tracker:
    """The event state of one publisher or subscription: counts, and the hooks that feed them.
    The entity's hot path calls on_sample / on_publish only when an event needs them."""

    def __init__(self, entity: Any, handlers: list[EventHandler]) -> None:
        self.entity = entity
        self.handlers = handlers
        self._lock = threading.Lock()
        qos = entity.qos_profile
        self.deadline_s = qos.deadline.nanoseconds / 1e9 if self._handler('DEADLINE_MISSED') else 0.0
        manual = qos.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC
        self.lease_s = qos.liveliness_lease_duration.nanoseconds / 1e9 \
            if manual and self._handler('LIVELINESS_LOST') else 0.0
        self.last_activity = self.last_assert = 0.0
        self.running: set[str] = set()  # watchdog entries: 'deadline', 'lease'
        self.deadline_total = self.liveliness_total = self.incompatible_total = self.lost_seen = 0
        self.matched: set[tuple] = set()
        self.matched_total = 0
        self.foreign: set[tuple] = set()
        self.last_incompatible: Entity | None = None
        # Types are compared by the node's QoS monitor as it walks the endpoints of the topic.
        self.graph_events = any(self._handler(n) for n in ('MATCHED', 'LIVELINESS_CHANGED'))
        entity._event_tracker = self
        if self.deadline_s or self.lease_s or self._handler('MESSAGE_LOST'):
            entity._events = self

    def _handler(self, suffix: str) -> EventHandler | None:
        for handler in self.handlers:
            if handler.event_type.name.endswith(suffix) and not handler._destroyed:
                return handler
        return None

    # hot path: a Zenoh thread for samples, the publishing thread for publishes
    def on_sample(self) -> None:
        self.last_activity = time.monotonic()
        if self.deadline_s and 'deadline' not in self.running:
            self._start('deadline', self.last_activity + self.deadline_s)
        lost = self.entity.lost
        if lost != self.lost_seen:
            change, self.lost_seen = lost - self.lost_seen, lost
            handler = self._handler('MESSAGE_LOST')
            if handler is not None:
                handler._fire(QoSMessageLostInfo(lost, change))

    def on_publish(self) -> None:
        self.last_activity = time.monotonic()
        if self.deadline_s and 'deadline' not in self.running:
            self._start('deadline', self.last_activity + self.deadline_s)
        self.on_assert()

    def on_assert(self) -> None:
        self.last_assert = time.monotonic()
        if self.lease_s and 'lease' not in self.running:
            self._start('lease', self.last_assert + self.lease_s)

    def _start(self, kind: str, due: float) -> None:
        with self._lock:
            if kind in self.running:
                return
            self.running.add(kind)
        _watchdog.schedule(due, self, kind)

    # watchdog thread
    def _due(self, kind: str, due: float) -> None:
        if self.entity._destroyed:
            return
        if kind == 'deadline':
            if self.last_activity + self.deadline_s > due:  # a message came: count from it
                _watchdog.schedule(self.last_activity + self.deadline_s, self, kind)
                return
            self.deadline_total += 1
            handler = self._handler('DEADLINE_MISSED')
            if handler is not None:
                payload = QoSRequestedDeadlineMissedInfo if _is_subscription(self.entity) else QoSOfferedDeadlineMissedInfo
                handler._fire(payload(self.deadline_total, 1))
            _watchdog.schedule(due + self.deadline_s, self, kind)
            return
        with self._lock:
            renewed = self.last_assert + self.lease_s > due
            if not renewed:
                self.running.discard('lease')  # lost until the next assertion starts a new lease
        if renewed:
            _watchdog.schedule(self.last_assert + self.lease_s, self, kind)
            return
        self.liveliness_total += 1
        handler = self._handler('LIVELINESS_LOST')
        if handler is not None:
            handler._fire(QoSLivelinessLostInfo(self.liveliness_total, 1))

    # the node's graph listener (a Zenoh thread)
    def graph_changed(self, entities: list[Entity]) -> None:
        mine = self.entity.graph_entity
        other_kind = EntityKind.PUBLISHER if mine.kind == EntityKind.SUBSCRIPTION else EntityKind.SUBSCRIPTION
        same = {(e.zid, e.node_id, e.entity_id) for e in entities
                if e.kind == other_kind and e.name == mine.name and same_type(mine, e)}
        with self._lock:
            before, self.matched = self.matched, same
            added = len(same - before)
            self.matched_total += added
        change = len(same) - len(before)
        handler = self._handler('MATCHED')
        if handler is not None and same != before:
            handler._fire(QoSSubscriptionMatchedInfo(self.matched_total, added, len(same), change))
        handler = self._handler('LIVELINESS_CHANGED')
        if handler is not None and change:
            handler._fire(QoSLivelinessChangedInfo(len(same), 0, change, 0))

    def incompatible_type(self, other: Entity) -> None:
        """The QoS monitor found `other`, an endpoint of the other side with another type."""
        key = (other.zid, other.node_id, other.entity_id)
        with self._lock:
            if key in self.foreign:
                return
            self.foreign.add(key)
            total = len(self.foreign)
        handler = self._handler('INCOMPATIBLE_TYPE')
        if handler is not None:
            handler._fire(IncompatibleTypeInfo(total, 1))

    def incompatible_qos(self, policy: QoSPolicyKind, other: Entity) -> None:
        handler = self._handler('INCOMPATIBLE_QOS')
        if handler is None:
            return
        with self._lock:
            self.incompatible_total += 1
            self.last_incompatible = other
            total = self.incompatible_total
        handler._fire(QoSRequestedIncompatibleQoSInfo(total, 1, policy))


def attach_event_callbacks(entity: Any, callbacks: SubscriptionEventCallbacks | PublisherEventCallbacks) -> None:
    """Create `entity`'s event handlers (registered with its node, which runs and destroys
    them) and what feeds them. Called by Node.create_publisher / create_subscription before
    the entity is announced, so the events of endpoints already there are not missed."""
    handlers = callbacks.create_event_handlers(entity.callback_group, entity, entity.topic_name)
    entity.event_handlers = handlers
    _Tracker(entity, handlers)
    for handler in handlers:
        entity._node._add(handler)


def report_incompatible_qos(entity: Any, policy: QoSPolicyKind, other: Entity) -> None:
    """One new incompatible endpoint `other` found for `entity` (by the node's QoS monitor).
    An entity made without event callbacks gets the default warning at once."""
    tracker = getattr(entity, '_event_tracker', None)
    if tracker is None:
        entity._node.get_logger().warn(_incompatible_text(entity, entity.topic_name, policy, other))
    else:
        tracker.incompatible_qos(policy, other)


def same_type(mine: Entity, other: Entity) -> bool:
    """Whether two endpoints of a topic exchange messages: the same type and definition."""
    return (mine.type, mine.type_hash) == (other.type, other.type_hash)


def report_incompatible_type(entity: Any, other: Entity) -> None:
    """`other`, an endpoint of the other side of `entity`'s topic, has another type (found by the
    node's QoS monitor): counted, and the incompatible-type handler, if any, fires once for it."""
    tracker = getattr(entity, '_event_tracker', None)
    if tracker is not None:
        tracker.incompatible_type(other)


def graph_changed(entity: Any, entities: list[Entity]) -> None:
    """The graph changed: update `entity`'s matches (if any event watches them)."""
    tracker = getattr(entity, '_event_tracker', None)
    if tracker is not None and tracker.graph_events:
        tracker.graph_changed(entities)
