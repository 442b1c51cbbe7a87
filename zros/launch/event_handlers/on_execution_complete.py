"""`OnExecutionComplete` (launch.event_handlers.on_execution_complete): when an action has
finished executing."""
from __future__ import annotations

from typing import Any

from zros.launch.errors import Origin
from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.execution_complete import ExecutionComplete
from zros.launch.origin import origin_here

__all__ = ['OnExecutionComplete']


class OnExecutionComplete(OnActionEventBase):
    """`OnExecutionComplete(target_action=action, on_completion=[...] or f(event, context))`."""

    event, _key, event_type = 'complete', 'on_completion', ExecutionComplete

    def __init__(self, *, target_action: Any = None, on_completion: Any, handle_once: bool = False,
                 origin: Origin | None = None) -> None:
        super().__init__(target_action=target_action, handler=on_completion, handle_once=handle_once,
                         origin=origin or origin_here('OnExecutionComplete'))
