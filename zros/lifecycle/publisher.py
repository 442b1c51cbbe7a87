"""LifecyclePublisher: a publisher that only publishes while its node is active."""
from __future__ import annotations

from typing import Any

from zros.lifecycle.managed_entity import SimpleManagedEntity
from zros.publisher import Publisher

__all__ = ['LifecyclePublisher']


class LifecyclePublisher(SimpleManagedEntity, Publisher):
    """Made by `LifecycleNode.create_lifecycle_publisher`. A message published while the node
    is not active is dropped, with one warning per inactive period (rclcpp's behaviour; rclpy
    drops silently)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        SimpleManagedEntity.__init__(self)
        Publisher.__init__(self, *args, **kwargs)
        self._warned = False

    def on_activate(self, state: Any) -> Any:
        self._warned = False
        return super().on_activate(state)

    def publish(self, msg: Any) -> None:
        if not self._enabled:
            if not self._warned:
                self._warned = True
                self._node.get_logger().warn(
                    f"Trying to publish message on the topic '{self.topic_name}', but the publisher is not activated")
            return
        Publisher.publish(self, msg)
