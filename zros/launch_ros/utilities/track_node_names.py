"""launch_ros.utilities.track_node_names: how many nodes of each fully qualified name a launch
has started, so a duplicate name can be warned about (ROS 2 graphs misbehave with them).

The count lives on the LaunchContext (`node_names`), which zros's resolver updates for each
node with an explicit name, so it covers nodes from every front end.
"""
from __future__ import annotations

from typing import Any

__all__ = ['add_node_name', 'get_node_name_count']


def add_node_name(context: Any, node_name: str) -> None:
    """Count one more node named `node_name` (a fully qualified name) in `context`."""
    context.node_names[node_name] += 1


def get_node_name_count(context: Any, node_name: str) -> int:
    """How many nodes named `node_name` `context` has counted (0 when none)."""
    return context.node_names.get(node_name, 0)
