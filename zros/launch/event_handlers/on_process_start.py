"""`OnProcessStart` (launch.event_handlers.on_process_start): when a process starts."""
from __future__ import annotations

from typing import Any

from zros.launch.errors import Origin
from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.process import ProcessStarted
from zros.launch.origin import origin_here

__all__ = ['OnProcessStart']


class OnProcessStart(OnActionEventBase):
    """`OnProcessStart(target_action=node, on_start=[...] or f(event, context))`."""

    event, _key, event_type = 'start', 'on_start', ProcessStarted

    def __init__(self, *, target_action: Any = None, on_start: Any, handle_once: bool = False,
                 origin: Origin | None = None) -> None:
        super().__init__(target_action=target_action, handler=on_start, handle_once=handle_once,
                         origin=origin or origin_here('OnProcessStart'))
