"""launch_ros.actions.lifecycle_node: launch_ros's module path of `LifecycleNode`, which zros keeps in
zros.launch.lifecycle (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.lifecycle import LifecycleNode

__all__ = ['LifecycleNode']
