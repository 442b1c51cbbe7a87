"""Subscriptions: samples arrive on a Zenoh thread, wait in a bounded queue, and are decoded
and handed to the callback on the executor.

The queue is the QoS depth (KEEP_LAST) and drops the oldest sample when full, counting the
drop in `dropped`; gaps in a publisher's sequence numbers, seen as samples arrive (before the
depth rule), are counted in `lost`; samples of the wrong type or that fail to decode are counted
in `rejected` and logged once per publisher. The executor is woken once per subscription with
work, not once per sample, so a burst costs Zenoh's thread no more than an append.
"""
from __future__ import annotations

import inspect
import time
from collections import deque
from typing import TYPE_CHECKING, Any, Callable

import msgpack

from zros.entity import QueuedEntity
from zros.graph import EntityKind
from zros.qos import DurabilityPolicy, QoSProfile
from zros.wire import describe_type, read_header, type_tail, writer_sequence

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Subscription', 'MessageInfo']

MessageInfo = dict  # {'source_timestamp', 'received_timestamp', 'publication_sequence_number', ...}


def _wants_info(callback: Callable) -> bool:
    """rclpy calls `callback(msg, info)` when the callback takes two positional arguments."""
    try:
        params = inspect.signature(callback).parameters.values()
    except (TypeError, ValueError):
        return False
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    return len(positional) >= 2 or any(p.kind == p.VAR_POSITIONAL for p in params)


class Subscription(QueuedEntity):
    """Made by `Node.create_subscription`."""

    _events: Any = None  # zros.event_handler's tracker, when a deadline or message-lost event needs it

    def __init__(self, node: 'Node', msg_type: type, topic: str, callback: Callable, qos: QoSProfile,
                 callback_group: Any, raw: bool = False) -> None:
        import zenoh
        import zenoh.ext
        from zros.keys import topic_key
        self._node = node  # the Zenoh callback may run before NodeEntity.__init__ below
        self.msg_type = msg_type
        self.topic_name = topic
        self.callback = callback
        self.qos_profile = qos
        self.callback_group = callback_group
        self.raw = raw
        self._with_info = _wants_info(callback)
        self._queue: deque = deque(maxlen=qos.queue_depth)
        self._tail = type_tail(msg_type)
        self._last_seq: dict[bytes, int] = {}
        self._complained: set[bytes] = set()
        self.dropped = 0
        self.lost = 0
        self.rejected = 0
        self.received = 0
        session = node.context.session
        key = topic_key(node.context.domain_id, topic)
        if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL:
            self._zenoh = zenoh.ext.declare_advanced_subscriber(
                session, key, self._on_sample,
                history=zenoh.ext.HistoryConfig(detect_late_publishers=True, max_samples=max(1, qos.queue_depth)),
                subscriber_detection=True)
        else:
            self._zenoh = session.declare_subscriber(key, self._on_sample)
        super().__init__(node, EntityKind.SUBSCRIPTION, topic, msg_type, qos)

    # Zenoh thread: copy out, count gaps, queue; never user code.
    def _on_sample(self, sample: Any) -> None:
        attachment = sample.attachment
        attachment = attachment.to_bytes() if attachment is not None else b''
        writer = writer_sequence(attachment)
        if writer is not None:
            gid, seq = writer
            last = self._last_seq.get(gid)
            if last is not None and seq > last + 1:
                self.lost += seq - last - 1
            self._last_seq[gid] = seq
        queue = self._queue
        if len(queue) == queue.maxlen:
            self.dropped += 1
        queue.append((sample.payload.to_bytes(), attachment, time.time_ns() if self._with_info else 0))
        self._arrived()
        if self._events is not None:
            self._events.on_sample()

    # Executor thread. spin_once takes one sample per call, as rclpy takes one message per
    # callback; spin() lets a subscription run up to `budget` waiting samples in one go.
    def _execute(self, budget: int = 1) -> None:
        queue = self._queue
        for _ in range(budget):
            if not queue:
                break
            self._deliver(*queue.popleft())
        self._rearm()

    def _deliver(self, payload: bytes, attachment: bytes, received: int) -> None:
        self.received += 1
        header = read_header(attachment)
        if header is not None:
            gid, seq, source_ns, tail = header
            if tail != self._tail:
                self._reject(gid, self._wrong_type_text(tail))
                return
        else:
            seq, source_ns, gid = 0, 0, b''
        if self.raw:
            msg = payload
        else:
            try:
                msg = self.msg_type._FROM_WIRE(msgpack.unpackb(payload))
            except Exception as exc:  # noqa: BLE001 - a corrupt or foreign payload must not kill the node
                self._reject(gid, f'payload is not a valid {self.msg_type._TYPE} ({type(exc).__name__}: {exc})')
                return
        if self._with_info:
            self.callback(msg, {'source_timestamp': source_ns, 'received_timestamp': received,
                                'publication_sequence_number': seq,
                                'reception_sequence_number': self.received})
        else:
            self.callback(msg)

    def _wrong_type_text(self, tail: bytes) -> str:
        their_type, their_hash = describe_type(tail)
        if their_type == self.msg_type._TYPE:
            return (f'a publisher sends {their_type} with a different definition '
                    f'(hash {their_hash}, expected {self.msg_type._HASH})')
        return f'a publisher sends {their_type}, this subscription expects {self.msg_type._TYPE}'

    def _reject(self, gid: bytes, reason: str) -> None:
        self.rejected += 1
        if gid not in self._complained:
            self._complained.add(gid)
            self._node.get_logger().error(
                f"dropping messages on '{self.topic_name}': {reason} (reported once per publisher)")
