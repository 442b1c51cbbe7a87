"""launch_ros.events.matches_node_name: aim an event (a lifecycle ChangeState) at the node
actions of one fully qualified name, rather than at one action object (`matches_action`)."""
from __future__ import annotations

from typing import Any, Callable

from zros.launch_ros.utilities.namespace_utils import make_namespace_absolute

__all__ = ['matches_node_name']


def matches_node_name(node_name: str) -> Callable[[Any], bool]:
    """A matcher for node actions whose `node_name` is `node_name` (made absolute: 'talker' is
    '/talker'); a node is matched once it has been executed and so knows its name."""
    wanted = make_namespace_absolute(node_name)

    def matcher(action: Any) -> bool:
        try:
            return getattr(action, 'node_name', None) == wanted
        except RuntimeError:   # a node action not executed yet has no name
            return False
    return matcher
