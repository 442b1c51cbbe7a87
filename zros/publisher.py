"""Publishers: typed messages out to a Zenoh key, stamped with zros.wire's attachment."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Generic

from zros.entity import NodeEntity
from zros.graph import EntityKind
from zros.message import MsgT, encoder
from zros.priority import transport_priority
from zros.typesupport import type_name_of
from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from zros.wire import AttachmentWriter

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['Publisher']


class Publisher(NodeEntity, Generic[MsgT]):
    """Sends messages of one type on one topic; made by `Node.create_publisher`, never directly.

    It owns its Zenoh publisher (declared on the topic's key) and its graph token; `destroy()`
    or `Node.destroy_publisher` undeclares both. Generic in the message type, so that an
    editor knows `publish` takes a `String` for a ``Publisher[String]``.
    """

    _events: Any = None  # zros.event_handler's tracker, when a deadline or liveliness event needs it

    def __init__(self, node: 'Node', msg_type: type[MsgT], topic: str, qos: QoSProfile, callback_group: Any) -> None:
        import zenoh
        import zenoh.ext
        from zros.keys import topic_key
        self.msg_type: Any = msg_type   # a class built at run time: its _TYPE is not declared
        self.topic_name = topic
        self.qos_profile = qos
        self.callback_group = callback_group
        session = node.context.session
        key = topic_key(node.context.domain_id, topic)
        reliable = qos.reliability != ReliabilityPolicy.BEST_EFFORT
        # zros.priority: a cmd_vel overtakes a map queued on a slow link
        self.transport_priority = transport_priority(topic, type_name_of(msg_type))
        options: dict[str, Any] = dict(
            congestion_control=zenoh.CongestionControl.BLOCK if reliable else zenoh.CongestionControl.DROP,
            reliability=zenoh.Reliability.RELIABLE if reliable else zenoh.Reliability.BEST_EFFORT,
            priority=getattr(zenoh.Priority, self.transport_priority.priority.upper()),
            express=self.transport_priority.express,
        )
        if qos.durability == DurabilityPolicy.TRANSIENT_LOCAL:
            self._zenoh = zenoh.ext.declare_advanced_publisher(
                session, key, cache=zenoh.ext.CacheConfig(max_samples=max(1, qos.queue_depth)),
                publisher_detection=True, **options)
        else:
            self._zenoh = session.declare_publisher(key, **options)
        self._put = self._zenoh.put
        self._encode: Callable[[Any], Any] = encoder(msg_type)   # takes MsgT, checked in publish
        self._stamp = AttachmentWriter(msg_type).next
        super().__init__(node, EntityKind.PUBLISHER, topic, msg_type, qos)

    def publish(self, msg: MsgT | bytes | bytearray) -> None:
        """Send a message to every matching subscription.

        Serialization happens on the calling thread; with RELIABLE QoS the call may block while
        Zenoh's queues are full.

        :param msg: An instance of the publisher's message type, or its already serialized bytes
            (as rclpy allows).
        :raises TypeError: If `msg` is of another type.
        :raises RuntimeError: If the publisher has been destroyed.
        """
        if type(msg) is self.msg_type:
            payload = self._encode(msg)
        elif isinstance(msg, (bytes, bytearray)):
            payload = bytes(msg)
        else:
            raise TypeError(
                f"publisher on '{self.topic_name}' expects {self.msg_type._TYPE}, "
                f"got {getattr(type(msg), '_TYPE', type(msg).__name__)}")
        if self._destroyed:
            raise RuntimeError(f"publisher on '{self.topic_name}' has been destroyed")
        self._put(payload, attachment=self._stamp())
        if self._events is not None:
            self._events.on_publish()

    #: What `publish` does, under the name the node's own channels (/rosout) send through, so
    #: that what wraps or replaces the public `publish` (a lifecycle publisher, a test's mock)
    #: sees only the program's messages, as in rclpy, where log lines never pass through a
    #: Publisher. The same function, not a call of it: one Python call less per message.
    _send = publish

    def assert_liveliness(self) -> None:
        """Tell the system this publisher is alive without publishing (MANUAL_BY_TOPIC
        liveliness: a lease that passes without this or a publish loses liveliness)."""
        if self._events is not None:
            self._events.on_assert()

    def get_subscription_count(self) -> int:
        """Count the subscriptions on this publisher's topic that the graph knows of now.

        zros counts them from the liveliness tokens in the graph (there is no rmw to ask), so a
        subscription that has just been created may be missing for a moment.

        :return: The number of subscriptions, local and remote.
        """
        return self._node.count_subscribers(self.topic_name)

    def wait_for_all_acked(self, timeout: Any = None) -> bool:
        """rclpy's wait for reliable subscribers to acknowledge what was published.

        Zenoh does not report per-message acknowledgements (nor does rmw_zenoh): a RELIABLE
        `publish()` returns once Zenoh's reliable transport holds the message, blocking while
        its queues are full, so nothing is left to wait for here.

        :param timeout: A Duration to wait at most (ignored: there is nothing to wait for).
        :return: ``True``.
        :raises RuntimeError: If the publisher has been destroyed.
        """
        if self._destroyed:
            raise RuntimeError(f"publisher on '{self.topic_name}' has been destroyed")
        return True

    def wait_for_subscribers(self, count: int = 1, timeout_sec: float | None = None) -> bool:
        """Block until `count` subscriptions on the topic are in the graph (`zros topic pub -w`).

        :param count: How many subscriptions to wait for.
        :param timeout_sec: Seconds to wait at most; ``None`` waits forever.
        :return: ``True`` if they matched, ``False`` on timeout.
        """
        return self._node.context.graph.wait_for(
            lambda entities: sum(1 for e in entities if e.kind == EntityKind.SUBSCRIPTION
                                 and e.name == self.topic_name) >= count, timeout_sec)
