"""`OnProcessStart` (launch.event_handlers.on_process_start): when a process starts."""
from __future__ import annotations

from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.process import ProcessStarted

__all__ = ['OnProcessStart']


class OnProcessStart(OnActionEventBase):
    """`OnProcessStart(target_action=action, on_start=[...] or f(event, context), handle_once=False)`."""

    event, _key, event_type = 'start', 'on_start', ProcessStarted
