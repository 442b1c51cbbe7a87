"""Subscriptions: samples arrive on a Zenoh thread, wait in a bounded queue, and are decoded
and handed to the callback on the executor.

The queue is the QoS depth (KEEP_LAST) and drops the oldest sample when full, counting the
drop in `dropped`; gaps in a publisher's sequence numbers are counted in `lost`; samples of the
wrong type or that fail to decode are counted in `rejected` and logged once per publisher.
"""
from __future__ import annotations

import inspect
import struct
import time
from collections import deque
from typing import TYPE_CHECKING, Any, Callable

import msgpack

from zros.graph import EntityKind
from zros.publisher import ATTACHMENT_MAGIC, attachment_tail
from zros.qos import DurabilityPolicy, QoSProfile

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Subscription', 'MessageInfo']

_SEQ_TIME = struct.Struct('<Qq')
_HEAD = len(ATTACHMENT_MAGIC) + 16
_TAIL_AT = _HEAD + _SEQ_TIME.size

MessageInfo = dict  # {'source_timestamp', 'received_timestamp', 'publication_sequence_number', ...}


def _wants_info(callback: Callable) -> bool:
    """rclpy calls `callback(msg, info)` when the callback takes two positional arguments."""
    try:
        params = inspect.signature(callback).parameters.values()
    except (TypeError, ValueError):
        return False
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    return len(positional) >= 2 or any(p.kind == p.VAR_POSITIONAL for p in params)


class Subscription:
    """Made by `Node.create_subscription`."""

    def __init__(self, node: 'Node', msg_type: type, topic: str, callback: Callable, qos: QoSProfile,
                 callback_group: Any, raw: bool = False) -> None:
        import zenoh
        import zenoh.ext
        from zros.keys import topic_key
        self._node = node
        self.msg_type = msg_type
        self.topic_name = topic
        self.callback = callback
        self.qos_profile = qos
        self.callback_group = callback_group
        self.raw = raw
        self._with_info = _wants_info(callback)
        self._queue: deque = deque(maxlen=qos.queue_depth)
        self._tail = attachment_tail(msg_type)
        self._last_seq: dict[bytes, int] = {}
        self._complained: set[bytes] = set()
        self.dropped = 0
        self.lost = 0
        self.rejected = 0
        self.received = 0
        session = node.context.session
        key = topic_key(node.context.domain_id, topic)
        if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL:
            self._sub = zenoh.ext.declare_advanced_subscriber(
                session, key, self._on_sample,
                history=zenoh.ext.HistoryConfig(detect_late_publishers=True, max_samples=max(1, qos.queue_depth)),
                subscriber_detection=True)
        else:
            self._sub = session.declare_subscriber(key, self._on_sample)
        self._entity = node._declare_entity(EntityKind.SUBSCRIPTION, topic, msg_type, qos)
        self._destroyed = False

    # Zenoh thread: copy out and queue, nothing else.
    def _on_sample(self, sample: Any) -> None:
        attachment = sample.attachment
        item = (sample.payload.to_bytes(), attachment.to_bytes() if attachment is not None else b'', time.time_ns())
        queue = self._queue
        if len(queue) == queue.maxlen:
            self.dropped += 1
        queue.append(item)
        executor = self._node._executor
        if executor is not None:
            executor._enqueue(self)

    def _has_work(self) -> bool:
        return bool(self._queue)

    # Executor thread.
    def _execute(self) -> None:
        try:
            payload, attachment, received = self._queue.popleft()
        except IndexError:
            return  # the sample this wake-up was for was dropped by the depth rule
        self.received += 1
        gid = attachment[2:_HEAD]
        if attachment[:2] == ATTACHMENT_MAGIC and len(attachment) >= _TAIL_AT:
            if attachment[_TAIL_AT:] != self._tail:
                self._reject(gid, self._wrong_type_text(attachment))
                return
            seq, source_ns = _SEQ_TIME.unpack_from(attachment, _HEAD)
            last = self._last_seq.get(gid)
            if last is not None and seq > last + 1:
                self.lost += seq - last - 1
            self._last_seq[gid] = seq
        else:
            seq, source_ns = 0, 0
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

    def _wrong_type_text(self, attachment: bytes) -> str:
        tail = attachment[_TAIL_AT:]
        their_type = tail[8:].decode(errors='replace')
        if their_type == self.msg_type._TYPE:
            return (f'a publisher sends {their_type} with a different definition '
                    f'(hash {tail[:8].hex()}, expected {self.msg_type._HASH})')
        return f'a publisher sends {their_type}, this subscription expects {self.msg_type._TYPE}'

    def _reject(self, gid: bytes, reason: str) -> None:
        self.rejected += 1
        if gid not in self._complained:
            self._complained.add(gid)
            self._node.get_logger().error(
                f"dropping messages on '{self.topic_name}': {reason} (reported once per publisher)")

    @property
    def handle(self) -> Any:
        return self._entity

    def destroy(self) -> None:
        if self._destroyed:
            return
        self._destroyed = True
        self._node._undeclare_entity(self._entity)
        try:
            self._sub.undeclare()
        except Exception:  # noqa: BLE001 - the session may be closing already
            pass
