"""launch_ros.actions.load_composable_nodes: launch_ros's module path of `LoadComposableNodes`
and `get_composable_node_load_request`, which zros keeps in the launch (zros.launch.actions.composable
and zros.launch.load_node), so importing them from here gives the one implementation."""
from __future__ import annotations

from zros.launch.actions.composable import LoadComposableNodes
from zros.launch.load_node import get_composable_node_load_request

__all__ = ['LoadComposableNodes', 'get_composable_node_load_request']
