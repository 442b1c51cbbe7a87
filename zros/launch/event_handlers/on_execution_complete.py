"""`OnExecutionComplete` (launch.event_handlers.on_execution_complete): when an action has
finished executing."""
from __future__ import annotations

from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.execution_complete import ExecutionComplete

__all__ = ['OnExecutionComplete']


class OnExecutionComplete(OnActionEventBase):
    """`OnExecutionComplete(target_action=action, on_completion=[...] or f(event, context), handle_once=False)`."""

    event, _key, event_type = 'complete', 'on_completion', ExecutionComplete
