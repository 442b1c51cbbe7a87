"""launch_ros.actions.composable_node_container: launch_ros's module path of `ComposableNodeContainer`, which zros keeps in
zros.launch.actions.composable (so importing it from here gives the one class)."""
from __future__ import annotations

from zros.launch.actions.composable import ComposableNodeContainer

__all__ = ['ComposableNodeContainer']
