"""launch_ros.events: the lifecycle events (`launch_ros.events.lifecycle`) and `matches_node_name`."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch_ros.events import lifecycle
from zros.launch_ros.events.matchers import matches_node_name

__all__ = ['lifecycle', 'matches_node_name']

__getattr__ = module_getattr(__name__)
