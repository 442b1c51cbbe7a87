"""tf2_ros.StaticTransformBroadcaster: latched transforms on /tf_static.

Every frame given to any `sendTransform` call is kept (keyed by child frame, a resend replaces
it) and the whole set is published each time, so a late joiner gets all of them. ROS 2 Humble's
Python broadcaster publishes only the last call's transforms on its depth-1 latched topic, so
a second call hides the first frame from late joiners (ros2/geometry2#585).
"""
from __future__ import annotations

import threading
from typing import Any, Iterable

from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, to_profile
from zros.tf2_ros.transform_broadcaster import as_list

__all__ = ['StaticTransformBroadcaster']

TF_STATIC_PUB_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, history=HistoryPolicy.KEEP_LAST)


class StaticTransformBroadcaster:
    """Publishes transforms that never change on /tf_static, latched for late joiners.

    :param node: The node that owns the /tf_static publisher.
    :param qos: A QoSProfile or depth; ``None`` gives depth 1, transient local (tf2_ros's).
    """
    def __init__(self, node: Any, qos: QoSProfile | int | None = None) -> None:
        from interfaces.tf2_msgs.msg import TFMessage
        self._msg_type = TFMessage
        self._frames: dict[str, Any] = {}
        self._lock = threading.Lock()
        self.pub_tf = node.create_publisher(TFMessage, '/tf_static',
                                            to_profile(qos) if qos is not None else TF_STATIC_PUB_QOS)

    def sendTransform(self, transform: Any | Iterable[Any]) -> None:  # noqa: N802 - tf2_ros's name
        """Add transforms to the broadcaster's set and publish the whole set.

        Unlike Humble's broadcaster, frames sent by earlier calls stay in the set (see the module
        docstring); sending a child frame again replaces its transform.

        :param transform: A geometry_msgs/msg/TransformStamped, or a list or tuple of them.
        """
        with self._lock:
            for t in as_list(transform):
                self._frames[t.child_frame_id] = t
            message = self._msg_type(transforms=list(self._frames.values()))
        self.pub_tf.publish(message)

    send_transform = sendTransform
