"""tf2_ros.TransformListener: keeps a Buffer filled from /tf and /tf_static.

The subscriptions appear in the graph under the listener's node, as in ROS (`zros node info`
lists /tf and /tf_static), but the Zenoh subscribers behind them are the process's shared
TfHub, which inserts on Zenoh's thread: the buffer fills whether or not the node spins.
`spin_thread` is therefore accepted and has nothing left to do. A message that reached the
buffer still counts as the listener's callback for the node's executor (one executor wake for
a burst, as a subscription's): rclpy code that sends a transform and then `spin_once()`s, to
let its listener take it, returns instead of waiting for some other callback.

`TransformException` is importable from here too, which ROS's module does not offer but course
material does (`from tf2_ros.transform_listener import TransformException`).
"""
from __future__ import annotations

from collections import deque
from typing import Any

from zros.entity import QueuedEntity
from zros.graph import EntityKind
from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, to_profile
from zros.tf2_ros.buffer import Buffer
from zros.tf2_ros.exceptions import TransformException
from zros.tf2_ros.listener_hub import TF_STATIC_TOPIC, TF_TOPIC, TfHub

__all__ = ['TransformListener', 'TransformException']

TF_QOS = QoSProfile(depth=100, durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
TF_STATIC_QOS = QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL, history=HistoryPolicy.KEEP_LAST)


class _SharedSubscription(QueuedEntity):
    """The graph entry of one listener topic; the data flows through the TfHub, which calls
    `_arrived` after filling the buffer (its queue holds only "something arrived")."""

    callback_group = None

    def __init__(self, node: Any, topic: str, qos: QoSProfile, hub: TfHub, buffer: Buffer, static: bool) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self.topic_name = topic
        self.qos_profile = qos
        self.msg_type = TFMessage
        self._queue: deque = deque(maxlen=1)
        self._hub, self._buffer, self._static = hub, buffer, static
        super().__init__(node, EntityKind.SUBSCRIPTION, topic, TFMessage, qos)
        hub.attach(buffer, node.get_clock(), static, self._arrived)

    def _arrived(self) -> None:  # Zenoh thread
        self._queue.append(True)
        if not self._scheduled:
            self._schedule()

    def _execute(self, budget: int = 1) -> None:  # the buffer has it already: nothing left to run
        self._queue.clear()
        self._rearm()

    def _feed(self, buffer: Buffer) -> None:
        """Feed `buffer` from now on instead of the one given at construction."""
        if buffer is not self._buffer:
            self._hub.detach(self._buffer, self._static)
            self._buffer = buffer
            self._hub.attach(buffer, self._node.get_clock(), self._static, self._arrived)

    def _release(self) -> None:
        self._hub.detach(self._buffer, self._static)


class TransformListener:
    """Feeds a Buffer with every transform published on /tf and /tf_static.

    Keep a reference to it for as long as the buffer should fill.

    :param buffer: The buffer to fill.
    :param node: The node the /tf subscriptions are listed under.
    :param spin_thread: Accepted for rclpy's signature; unnecessary in zros (see the module
        docstring).
    :param qos: QoS of the /tf subscription (depth 100, volatile by default).
    :param static_qos: QoS of the /tf_static subscription (depth 100, transient local).
    """

    def __init__(self, buffer: Buffer, node: Any, *, spin_thread: bool = False,
                 qos: QoSProfile | int | None = None, static_qos: QoSProfile | int | None = None) -> None:
        self._buffer = buffer
        self.node = node
        hub = TfHub.for_context(node.context)
        self.tf_sub = node._add(_SharedSubscription(node, TF_TOPIC, to_profile(qos) if qos is not None else TF_QOS,
                                                    hub, buffer, False))
        self.tf_static_sub = node._add(_SharedSubscription(
            node, TF_STATIC_TOPIC, to_profile(static_qos) if static_qos is not None else TF_STATIC_QOS,
            hub, buffer, True))

    @property
    def buffer(self) -> Buffer:
        """The buffer this listener fills; assigning another one moves the feed to it (rclpy's
        listener reads `self.buffer` in its callback, so code swaps buffers that way)."""
        return self._buffer

    @buffer.setter
    def buffer(self, buffer: Buffer) -> None:
        self._buffer = buffer
        for subscription in (getattr(self, 'tf_sub', None), getattr(self, 'tf_static_sub', None)):
            if subscription is not None:
                subscription._feed(buffer)

    def unregister(self) -> None:
        """Stop feeding the buffer (destroy_node does this too)."""
        self.node._destroy_entity(self.tf_sub)
        self.node._destroy_entity(self.tf_static_sub)
