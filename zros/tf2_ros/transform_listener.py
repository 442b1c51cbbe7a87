"""tf2_ros.TransformListener: keeps a Buffer filled from /tf and /tf_static.

The subscriptions appear in the graph under the listener's node, as in ROS (`zros node info`
lists /tf and /tf_static), but the Zenoh subscribers behind them are the process's shared
TfHub, which inserts on Zenoh's thread: the buffer fills whether or not the node spins.
`spin_thread` is therefore accepted and has nothing left to do.

`TransformException` is importable from here too, which ROS's module does not offer but course
material does (`from tf2_ros.transform_listener import TransformException`).
"""
from __future__ import annotations

from typing import Any

from zros.entity import NodeEntity
from zros.graph import EntityKind
from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, to_profile
from zros.tf2_ros.buffer import Buffer
from zros.tf2_ros.exceptions import TransformException
from zros.tf2_ros.listener_hub import TF_STATIC_TOPIC, TF_TOPIC, TfHub

__all__ = ['TransformListener', 'TransformException']

TF_QOS = QoSProfile(depth=100, durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
TF_STATIC_QOS = QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL, history=HistoryPolicy.KEEP_LAST)


class _SharedSubscription(NodeEntity):
    """The graph entry of one listener topic; the data flows through the TfHub."""

    def __init__(self, node: Any, topic: str, qos: QoSProfile, hub: TfHub, buffer: Buffer, static: bool) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self.topic_name = topic
        self.qos_profile = qos
        self.msg_type = TFMessage
        self._hub, self._buffer, self._static = hub, buffer, static
        super().__init__(node, EntityKind.SUBSCRIPTION, topic, TFMessage, qos)
        hub.attach(buffer, node.get_clock(), static)

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
        self.buffer = buffer
        self.node = node
        hub = TfHub.for_context(node.context)
        self.tf_sub = node._add(_SharedSubscription(node, TF_TOPIC, to_profile(qos) if qos is not None else TF_QOS,
                                                    hub, buffer, False))
        self.tf_static_sub = node._add(_SharedSubscription(
            node, TF_STATIC_TOPIC, to_profile(static_qos) if static_qos is not None else TF_STATIC_QOS,
            hub, buffer, True))

    def unregister(self) -> None:
        """Stop feeding the buffer (destroy_node does this too)."""
        self.node._destroy_entity(self.tf_sub)
        self.node._destroy_entity(self.tf_static_sub)
