"""launch_ros.descriptions.composable_node: launch_ros's module path of `ComposableNode`, which
zros keeps with the composable-node actions in zros.launch.actions.composable."""
from __future__ import annotations

from zros.launch.actions.composable import ComposableNode

__all__ = ['ComposableNode']
