"""Publishers: typed messages out to a Zenoh key, with the sample attachment of protocol v1.

Attachment (docs/protocol.md): b'Z1' | gid (16 bytes) | seq (u64 LE) | source time ns (i64 LE)
| type hash (8 bytes) | type name (UTF-8). Subscribers use it to reject the wrong type, to count
lost messages per publisher and to report source timestamps.
"""
from __future__ import annotations

import itertools
import os
import struct
import time
from typing import TYPE_CHECKING, Any

import msgpack

from zros.graph import Entity, EntityKind
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Publisher', 'ATTACHMENT_MAGIC', 'attachment_tail']

ATTACHMENT_MAGIC = b'Z1'
_SEQ_TIME = struct.Struct('<Qq')


def attachment_tail(msg_type: type) -> bytes:
    """The type-identifying end of every attachment for `msg_type`."""
    return bytes.fromhex(msg_type._HASH) + msg_type._TYPE.encode()


class Publisher:
    """Made by `Node.create_publisher`; publishes instances of one message type on one topic."""

    def __init__(self, node: 'Node', msg_type: type, topic: str, qos: QoSProfile, callback_group: Any) -> None:
        import zenoh
        import zenoh.ext
        from zros.keys import topic_key
        self._node = node
        self.msg_type = msg_type
        self.topic_name = topic
        self.qos_profile = qos
        self.callback_group = callback_group
        session = node.context.session
        key = topic_key(node.context.domain_id, topic)
        reliable = qos.reliability != ReliabilityPolicy.BEST_EFFORT
        options = dict(
            congestion_control=zenoh.CongestionControl.BLOCK if reliable else zenoh.CongestionControl.DROP,
            reliability=zenoh.Reliability.RELIABLE if reliable else zenoh.Reliability.BEST_EFFORT,
        )
        if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL:
            self._pub = zenoh.ext.declare_advanced_publisher(
                session, key, cache=zenoh.ext.CacheConfig(max_samples=max(1, qos.queue_depth)),
                publisher_detection=True, **options)
        else:
            self._pub = session.declare_publisher(key, **options)
        gid = os.urandom(16)
        self._att_head = ATTACHMENT_MAGIC + gid
        self._att_tail = attachment_tail(msg_type)
        self._seq = itertools.count(1)
        self._entity = node._declare_entity(EntityKind.PUBLISHER, topic, msg_type, qos)
        self._destroyed = False

    def publish(self, msg: Any) -> None:
        """Send `msg` (an instance of this publisher's type) to every matching subscription."""
        if type(msg) is not self.msg_type:
            raise TypeError(
                f"publisher on '{self.topic_name}' expects {self.msg_type._TYPE}, "
                f"got {getattr(type(msg), '_TYPE', type(msg).__name__)}")
        if self._destroyed:
            raise RuntimeError(f"publisher on '{self.topic_name}' has been destroyed")
        payload = msgpack.packb(msg._TO_WIRE(msg))
        attachment = self._att_head + _SEQ_TIME.pack(next(self._seq), time.time_ns()) + self._att_tail
        self._pub.put(payload, attachment=attachment)

    @property
    def handle(self) -> Entity:
        return self._entity

    def get_subscription_count(self) -> int:
        return self._node.count_subscribers(self.topic_name)

    def wait_for_subscribers(self, count: int = 1, timeout_sec: float | None = None) -> bool:
        """Block until `count` subscriptions match (used by `zros topic pub -w`)."""
        return self._node.context.graph.wait_for(
            lambda entities: sum(1 for e in entities if e.kind == EntityKind.SUBSCRIPTION
                                 and e.name == self.topic_name) >= count, timeout_sec)

    def destroy(self) -> None:
        if self._destroyed:
            return
        self._destroyed = True
        self._node._undeclare_entity(self._entity)
        try:
            self._pub.undeclare()
        except Exception:  # noqa: BLE001 - the session may be closing already
            pass
