"""`Shutdown` (launch.events.Shutdown): the event that ends a launch."""
from __future__ import annotations

from typing import Any

from zros.launch.event import Event

__all__ = ['Shutdown']


class Shutdown(Event):
    """`EmitEvent(event=Shutdown(reason='...'))` stops the whole launch; `due_to_sigint` says
    whether Ctrl-C asked for it."""

    name = 'launch.events.Shutdown'

    def __init__(self, *, reason: Any = None, due_to_sigint: bool = False) -> None:
        self.reason = reason
        self.due_to_sigint = due_to_sigint

    def __repr__(self) -> str:
        return f'<Shutdown reason={self.reason!r}>'
