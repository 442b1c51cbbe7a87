"""`ExecutionComplete` (launch.events): an action has finished executing (OnExecutionComplete
waits for it)."""
from __future__ import annotations

from typing import Any

from zros.launch.event import Event

__all__ = ['ExecutionComplete']


class ExecutionComplete(Event):
    """`action` finished executing."""

    name = 'launch.events.ExecutionComplete'

    def __init__(self, *, action: Any) -> None:
        self.action = action

    def __repr__(self) -> str:
        return f'<ExecutionComplete of {self.action!r}>'
