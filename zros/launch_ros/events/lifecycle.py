"""launch_ros.events.lifecycle: `ChangeState` (ask a LifecycleNode for a transition) and
`StateTransition` (a step it went through), zros.launch.lifecycle's."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch.lifecycle import ChangeState, StateTransition

__all__ = ['ChangeState', 'StateTransition']

__getattr__ = module_getattr(__name__)
