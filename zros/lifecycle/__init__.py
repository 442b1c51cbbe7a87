"""zros.lifecycle: rclpy.lifecycle's managed nodes on zros.

    from zros.lifecycle import LifecycleNode, State, TransitionCallbackReturn

    class Driver(LifecycleNode):
        def on_configure(self, state: State) -> TransitionCallbackReturn:
            self.pub = self.create_lifecycle_publisher(String, 'status', 10)
            return TransitionCallbackReturn.SUCCESS

`LifecycleClient` drives another node's lifecycle from Python (what the lifecycle manager,
`zros lifecycle` and navigation helpers use).
"""
from __future__ import annotations

from zros.lifecycle.client import LifecycleClient
from zros.lifecycle.managed_entity import ManagedEntity, SimpleManagedEntity
from zros.lifecycle.node import LifecycleNode, LifecycleNodeMixin
from zros.lifecycle.publisher import LifecyclePublisher
from zros.lifecycle.state_machine import LifecycleState, TransitionCallbackReturn, TransitionError

# As rclpy.lifecycle: `from zros.lifecycle import Node, State, Publisher` work too.
Node = LifecycleNode
NodeMixin = LifecycleNodeMixin
State = LifecycleState
Publisher = LifecyclePublisher

__all__ = ['LifecycleNode', 'LifecycleNodeMixin', 'LifecycleState', 'LifecyclePublisher', 'ManagedEntity',
           'SimpleManagedEntity', 'TransitionCallbackReturn', 'TransitionError', 'LifecycleClient']
