"""Subscriptions: samples arrive on a Zenoh thread, wait in a bounded queue, and are decoded
and handed to the callback on the executor.

The queue is the QoS depth (KEEP_LAST) and drops the oldest sample when full, counting the
drop in `dropped`; gaps in a publisher's sequence numbers, seen as samples arrive (before the
depth rule), are counted in `lost`; samples of the wrong type, larger than the size limit
(zros.wire.max_message_size) or that do not decode strictly as the subscription's type are
counted in `rejected` and logged once per publisher: a malformed sample never reaches the
callback. What the callback does with a well-formed message is its own business: an exception
it raises propagates out of spin(), as in rclpy. The executor is woken once per subscription with
work, not once per sample, so a burst costs Zenoh's thread no more than an append.
"""
from __future__ import annotations

import inspect
import time
from collections import deque
from typing import TYPE_CHECKING, Any, Callable

from zros.entity import QueuedEntity
from zros.errors import DecodeError
from zros.graph import EntityKind
from zros.message import deserialize
from zros.qos import DurabilityPolicy, QoSProfile
from zros.wire import (foreign_protocol, max_message_size, mismatch_reason, read_header, type_tail,
                       writer_sequence)

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Subscription', 'MessageInfo']

# How many publishers' rejected samples a subscription logs (one line each).
_MAX_REPORTED = 16

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
        self._max_size = max_message_size()
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
        payload = sample.payload
        if len(payload) > self._max_size:  # refused before it is copied or decoded
            self.received += 1
            writer = writer_sequence(attachment)
            self._reject(writer[0] if writer else b'', f'a message of {len(payload)} bytes is larger than the limit of '
                                           f'{self._max_size} bytes (ZROS_MAX_MESSAGE_SIZE)')
            return
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
        queue.append((payload.to_bytes(), attachment, time.time_ns() if self._with_info else 0))
        self._arrived()
        if self._events is not None:
            self._events.on_sample()

    # Executor thread. spin_once takes one sample per call, as rclpy takes one message per
    # callback; spin() lets a subscription run up to `budget` waiting samples in one go.
    def _execute(self, budget: int = 1) -> Any:
        queue = self._queue
        pending = None
        for _ in range(budget):
            if not queue:
                break
            pending = self._deliver(*queue.popleft())
            if pending is not None:
                break   # an async callback's coroutine: the executor runs it as a task first
        self._rearm()
        return pending

    def _deliver(self, payload: bytes, attachment: bytes, received: int) -> Any:
        self.received += 1
        header = read_header(attachment)
        if header is not None:
            gid, seq, source_ns, tail = header
            if tail != self._tail:
                self._reject(gid, mismatch_reason(tail, self.msg_type, 'a publisher'))
                return
        else:
            seq, source_ns, gid = 0, 0, b''
            old = foreign_protocol(attachment)
            if old is not None:
                self._reject(gid, old)
                return
        if self.raw:
            msg = payload
        else:
            try:
                msg = deserialize(payload, self.msg_type)
            except DecodeError as exc:
                self._reject(gid, str(exc))
                return
        if self._with_info:
            return self.callback(msg, {'source_timestamp': source_ns, 'received_timestamp': received,
                                       'publication_sequence_number': seq,
                                       'reception_sequence_number': self.received})
        return self.callback(msg)

    def _reject(self, gid: bytes, reason: str) -> None:
        """Count a refused sample; log the first one of each publisher (senders without a zros
        attachment are one publisher, b''), and stop logging after _MAX_REPORTED of them so
        that forged publisher ids cannot flood the log."""
        self.rejected += 1
        if gid in self._complained or len(self._complained) > _MAX_REPORTED:
            return
        self._complained.add(gid)
        if len(self._complained) > _MAX_REPORTED:
            reason = f'{reason}; more publishers send bad samples: they are counted, not logged'
        self._node.get_logger().error(
            f"dropping messages on '{self.topic_name}': {reason} (reported once per publisher)")
