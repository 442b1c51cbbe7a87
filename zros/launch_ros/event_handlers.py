"""launch_ros.event_handlers: `OnStateTransition`, zros.launch.lifecycle's."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch.lifecycle import OnStateTransition

__all__ = ['OnStateTransition']

__getattr__ = module_getattr(__name__)
