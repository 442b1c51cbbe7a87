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

import importlib
from typing import Any

__all__ = ['LifecycleNode', 'LifecycleNodeMixin', 'LifecycleState', 'LifecyclePublisher', 'ManagedEntity',
           'SimpleManagedEntity', 'TransitionCallbackReturn', 'TransitionError', 'LifecycleClient']

# Loaded on first use, so that `zros.lifecycle.state_machine` and `zros.lifecycle.autostart`
# (plain data, what the launch reads while resolving a file) do not pull in the node and its
# transport. As rclpy.lifecycle: `from zros.lifecycle import Node, State, Publisher` work too.
_HOMES = {
    'LifecycleClient': ('zros.lifecycle.client', 'LifecycleClient'),
    'ManagedEntity': ('zros.lifecycle.managed_entity', 'ManagedEntity'),
    'SimpleManagedEntity': ('zros.lifecycle.managed_entity', 'SimpleManagedEntity'),
    'LifecycleNode': ('zros.lifecycle.node', 'LifecycleNode'),
    'Node': ('zros.lifecycle.node', 'LifecycleNode'),
    'LifecycleNodeMixin': ('zros.lifecycle.node', 'LifecycleNodeMixin'),
    'NodeMixin': ('zros.lifecycle.node', 'LifecycleNodeMixin'),
    'LifecyclePublisher': ('zros.lifecycle.publisher', 'LifecyclePublisher'),
    'Publisher': ('zros.lifecycle.publisher', 'LifecyclePublisher'),
    'LifecycleState': ('zros.lifecycle.state_machine', 'LifecycleState'),
    'State': ('zros.lifecycle.state_machine', 'LifecycleState'),
    'TransitionCallbackReturn': ('zros.lifecycle.state_machine', 'TransitionCallbackReturn'),
    'TransitionError': ('zros.lifecycle.state_machine', 'TransitionError'),
}


def __getattr__(name: str) -> Any:
    try:
        module, attribute = _HOMES[name]
    except KeyError:
        raise AttributeError(f"module 'zros.lifecycle' has no attribute '{name}'") from None
    value = getattr(importlib.import_module(module), attribute)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOMES))
