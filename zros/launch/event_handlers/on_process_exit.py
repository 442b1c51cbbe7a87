"""`OnProcessExit` (launch.event_handlers.on_process_exit): when a process exits."""
from __future__ import annotations

from typing import Any

from zros.launch.errors import Origin
from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.process import ProcessExited
from zros.launch.origin import origin_here

__all__ = ['OnProcessExit']


class OnProcessExit(OnActionEventBase):
    """`OnProcessExit(target_action=node, on_exit=[...] or f(event, context))`; the function
    reads `event.returncode`."""

    event, _key, event_type = 'exit', 'on_exit', ProcessExited

    def __init__(self, *, target_action: Any = None, on_exit: Any, handle_once: bool = False,
                 origin: Origin | None = None) -> None:
        super().__init__(target_action=target_action, handler=on_exit, handle_once=handle_once,
                         origin=origin or origin_here('OnProcessExit'))
