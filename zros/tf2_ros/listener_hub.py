"""One /tf and one /tf_static subscription per process, shared by every TransformListener.

A process with several listeners (several nodes, or a node that makes a listener per helper
class) would otherwise decode every TF message once per listener. The hub decodes each sample
once (strictly, as every zros reader does) and inserts it into every registered buffer on
Zenoh's receive thread. Static transforms are remembered, so a listener
created later in the same process gets them at once, as a late-joining process does from the
transient-local history.

With simulated time, a clock that jumps back (a reset simulation, a looping bag) would leave
"future" data in the buffers and every lookup would fail; the hub clears a buffer when its
listener's clock goes back by more than a second, as rclcpp's listener does.
"""
from __future__ import annotations

import threading
import weakref
from typing import Any

from zros.errors import DecodeError
from zros.graph import undeclare_quietly
from zros.logging import get_logger
from zros.message import deserialize
from zros.wire import WAKE, mismatch_reason, read_header, type_tail

__all__ = ['TfHub', 'TF_TOPIC', 'TF_STATIC_TOPIC']

TF_TOPIC = '/tf'
TF_STATIC_TOPIC = '/tf_static'
_AUTHORITY = 'default_authority'
_JUMP_BACK_NS = 1_000_000_000
# How long before a jump back a message may have been stamped and still be taken for stale.
_STALE_WINDOW_NS = 5_000_000_000

_hubs: 'weakref.WeakKeyDictionary[Any, TfHub]' = weakref.WeakKeyDictionary()
_hubs_lock = threading.Lock()
_logger = get_logger('tf2_listener')


class _Target:
    """A registered buffer and the clock of the listener that registered it."""

    __slots__ = ('buffer', 'clock', 'last_now', 'notify', 'before_jump')

    def __init__(self, buffer: Any, clock: Any, notify: Any) -> None:
        self.buffer, self.clock, self.last_now, self.notify = buffer, clock, 0, notify
        self.before_jump: int | None = None   # the time a jump back left, while stale data may still come

    def check_clock(self) -> int | None:
        """Clear the buffer when the clock went back; returns the clock's time (None on
        system time)."""
        clock = self.clock
        if clock is None or not getattr(clock, 'ros_time_is_active', False):
            return None
        now = clock.now().nanoseconds
        if now + _JUMP_BACK_NS < self.last_now:
            _logger.warn('Detected jump back in time. Clearing TF buffer.')
            self.buffer.clear()
            self.before_jump = self.last_now
        self.last_now = now
        return now

    def stale(self, now: int | None, items: list) -> bool:
        """After a jump back, a message stamped from before it (sent before the reset, delivered
        after) would refill the cleared buffer with the future, and tf2 then refuses the new
        data as too old: it is dropped until the clock has caught up with the jump."""
        if self.before_jump is None or now is None:
            return False
        if now + _JUMP_BACK_NS >= self.before_jump:
            self.before_jump = None
            return False
        # stamped ahead of the clock *and* near the time the jump left: data sent just before the
        # reset (a lagging clock under load must not make fresh data look stale)
        since = self.before_jump - _STALE_WINDOW_NS
        return any(item[2] > now + _JUMP_BACK_NS and item[2] >= since for item in items)


class TfHub:
    """Made on demand by `TfHub.for_context`; closed when the context shuts down."""

    def __init__(self, context: Any) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self._context = context
        self._type = TFMessage
        self._tail = type_tail(TFMessage)
        self._lock = threading.Lock()
        self._targets: dict[bool, tuple[_Target, ...]] = {False: (), True: ()}
        self._subscribers: dict[bool, Any] = {}
        self._static: dict[str, tuple[str, str, int, tuple]] = {}
        self._complained: set[bytes] = set()
        context.on_shutdown(self.close)

    @classmethod
    def for_context(cls, context: Any) -> 'TfHub':
        with _hubs_lock:
            hub = _hubs.get(context)
            if hub is None:
                hub = _hubs[context] = cls(context)
            return hub

    def attach(self, buffer: Any, clock: Any, static: bool, notify: Any = None) -> None:
        """Start feeding `buffer` from /tf (static=False) or /tf_static (static=True); `notify()`
        is called after each message that reached it."""
        with self._lock:
            if any(t.buffer is buffer for t in self._targets[static]):
                return
            self._targets[static] = self._targets[static] + (_Target(buffer, clock, notify),)
            if static not in self._subscribers:
                self._subscribers[static] = self._declare(static)
            replay = list(self._static.values()) if static else []
        if replay:
            buffer._insert_many(replay, _AUTHORITY, True, b'')

    def detach(self, buffer: Any, static: bool) -> None:
        with self._lock:
            self._targets[static] = tuple(t for t in self._targets[static] if t.buffer is not buffer)
            if self._targets[static]:
                return
            subscriber = self._subscribers.pop(static, None)
        undeclare_quietly(subscriber)

    def close(self) -> None:
        with self._lock:
            subscribers = list(self._subscribers.values())
            self._subscribers.clear()
            self._targets = {False: (), True: ()}
        for subscriber in subscribers:
            undeclare_quietly(subscriber)
        with _hubs_lock:
            _hubs.pop(self._context, None)

    def _declare(self, static: bool) -> Any:
        import zenoh.ext
        from zros.keys import topic_key
        session = self._context.session
        if static:
            key = topic_key(self._context.domain_id, TF_STATIC_TOPIC)
            return zenoh.ext.declare_advanced_subscriber(
                session, key, self._on_static,
                history=zenoh.ext.HistoryConfig(detect_late_publishers=True, max_samples=100),
                subscriber_detection=True)
        return session.declare_subscriber(topic_key(self._context.domain_id, TF_TOPIC), self._on_tf)

    # Zenoh threads ------------------------------------------------------------------------------
    def _on_tf(self, sample: Any) -> None:
        decoded = self._decode(sample, TF_TOPIC)
        if decoded is None:
            return
        writer, items = decoded
        for target in self._targets[False]:
            if target.stale(target.check_clock(), items):
                continue
            target.buffer._insert_many(items, _AUTHORITY, False, writer)
            if target.notify is not None:
                target.notify()

    def _on_static(self, sample: Any) -> None:
        decoded = self._decode(sample, TF_STATIC_TOPIC)
        if decoded is None:
            return
        writer, items = decoded
        with self._lock:
            for item in items:
                self._static[item[0]] = item
        for target in self._targets[True]:
            target.buffer._insert_many(items, _AUTHORITY, True, writer)
            if target.notify is not None:
                target.notify()

    def _decode(self, sample: Any, topic: str) -> tuple[bytes, list] | None:
        attachment = sample.attachment
        attachment = attachment.to_bytes() if attachment is not None else b''
        if attachment == WAKE:
            return None   # an executor's wake-up for a subscription of this topic (zros.executors)
        header = read_header(attachment)
        writer = header[0] if header is not None else b''
        if header is not None and header[3] != self._tail:
            self._complain(writer, mismatch_reason(header[3], self._type, 'a publisher'), topic)
            return None
        try:
            message = deserialize(sample.payload.to_bytes(), self._type)
        except DecodeError as exc:  # a corrupt or foreign payload must not kill the listener
            self._complain(writer, str(exc), topic)
            return None
        items = []
        for t in message.transforms:
            h, tr = t.header, t.transform
            p, q = tr.translation, tr.rotation
            items.append((t.child_frame_id, h.frame_id, h.stamp.sec * 1_000_000_000 + h.stamp.nanosec,
                          (p.x, p.y, p.z, q.x, q.y, q.z, q.w)))
        return writer, items

    def _complain(self, writer: bytes, reason: str, topic: str) -> None:
        if writer not in self._complained:
            self._complained.add(writer)
            _logger.error(f"dropping messages on '{topic}': {reason} (reported once per publisher)")
