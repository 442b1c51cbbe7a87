"""`OnProcessExit` (launch.event_handlers.on_process_exit): when a process exits; a function
reads `event.returncode`."""
from __future__ import annotations

from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.process import ProcessExited

__all__ = ['OnProcessExit']


class OnProcessExit(OnActionEventBase):
    """`OnProcessExit(target_action=action, on_exit=[...] or f(event, context), handle_once=False)`."""

    event, _key, event_type = 'exit', 'on_exit', ProcessExited
