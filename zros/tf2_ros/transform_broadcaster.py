"""tf2_ros.TransformBroadcaster: publishes transforms on /tf (depth 100, volatile)."""
from __future__ import annotations

from typing import Any, Iterable

from zros.qos import QoSProfile, to_profile

__all__ = ['TransformBroadcaster']


def as_list(transform: Any) -> list:
    """sendTransform takes one TransformStamped or a sequence of them."""
    return list(transform) if isinstance(transform, (list, tuple)) else [transform]


class TransformBroadcaster:
    """Publishes transforms on /tf, as tf2_ros.TransformBroadcaster.

    :param node: The node that owns the /tf publisher.
    :param qos: A QoSProfile or depth; ``None`` gives depth 100, volatile (tf2_ros's default).
    """
    def __init__(self, node: Any, qos: QoSProfile | int | None = None) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self._msg_type = TFMessage
        self.pub_tf = node.create_publisher(TFMessage, '/tf', to_profile(qos) if qos is not None else QoSProfile(depth=100))

    def sendTransform(self, transform: Any | Iterable[Any]) -> None:  # noqa: N802 - tf2_ros's name
        """Publish one transform or several in one TFMessage.

        :param transform: A geometry_msgs/msg/TransformStamped, or a list or tuple of them.
        """
        self.pub_tf.publish(self._msg_type(transforms=as_list(transform)))

    send_transform = sendTransform
