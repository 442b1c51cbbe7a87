"""`OnIncludeLaunchDescription` (launch.event_handlers): the launch's own handler that answers
an IncludeLaunchDescription event with its description, to be visited."""
from __future__ import annotations

from typing import Any

from zros.launch.event_handler import BaseEventHandler
from zros.launch.events.include_launch_description import IncludeLaunchDescription

__all__ = ['OnIncludeLaunchDescription']


class OnIncludeLaunchDescription(BaseEventHandler):
    """Matches IncludeLaunchDescription; `handle` returns the event's launch description."""

    def __init__(self, *, handle_once: bool = False) -> None:
        super().__init__(matcher=lambda event: isinstance(event, IncludeLaunchDescription), handle_once=handle_once)

    def handle(self, event: Any, context: Any) -> Any:
        super().handle(event, context)
        return event.launch_description
