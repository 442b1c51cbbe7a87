"""tf2_ros.TransformBroadcaster: publishes transforms on /tf (depth 100, volatile)."""
from __future__ import annotations

from typing import Any, Iterable

from zros.qos import QoSProfile, to_profile

__all__ = ['TransformBroadcaster']


def as_list(transform: Any) -> list:
    """sendTransform takes one TransformStamped or a sequence of them."""
    return list(transform) if isinstance(transform, (list, tuple)) else [transform]


class TransformBroadcaster:
    def __init__(self, node: Any, qos: QoSProfile | int | None = None) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self._msg_type = TFMessage
        self.pub_tf = node.create_publisher(TFMessage, '/tf', to_profile(qos) if qos is not None else QoSProfile(depth=100))

    def sendTransform(self, transform: Any | Iterable[Any]) -> None:  # noqa: N802 - tf2_ros's name
        self.pub_tf.publish(self._msg_type(transforms=as_list(transform)))

    send_transform = sendTransform
