"""launch_ros.events: the lifecycle events (`launch_ros.events.lifecycle`)."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch_ros.events import lifecycle

__all__ = ['lifecycle']

__getattr__ = module_getattr(__name__)
