"""The event side of a launch context (launch.LaunchContext's): the event queue, the handlers
registered on it, and the locals a handler's entities see (`context.locals.event`).

LaunchContext inherits it; zros.launch.launch_service drains the queue while the launch runs.
Handlers are offered an event newest first (as in launch), so a user's handler sees an event
before the launch's own.
"""
from __future__ import annotations

import queue
from collections import deque
from types import SimpleNamespace
from typing import Any

__all__ = ['EventDispatch']


class EventDispatch:
    """Queue, handlers and locals. Any thread may emit; one thread (the launch's) drains."""

    def __init__(self) -> None:
        self._event_queue: queue.Queue = queue.Queue()
        self._event_handlers: deque = deque()
        self._locals_stack: list[dict[str, Any]] = [{}]
        self._wakeup = lambda: None     # set by the running LaunchService: drain the queue now

    # -- handlers ------------------------------------------------------------------------------
    def register_event_handler(self, event_handler: Any, append: bool = False) -> None:
        """Offer events to `event_handler`: before the others, or after them with `append`."""
        if append:
            self._event_handlers.append(event_handler)
        else:
            self._event_handlers.appendleft(event_handler)

    def unregister_event_handler(self, event_handler: Any) -> None:
        """Raises ValueError if it is not registered (a handle_once handler handled twice)."""
        self._event_handlers.remove(event_handler)

    @property
    def event_handlers(self) -> list:
        return list(self._event_handlers)

    # -- events --------------------------------------------------------------------------------
    def emit_event_sync(self, event: Any) -> None:
        """Queue `event` for the handlers; from any thread."""
        self._event_queue.put(event)
        self._wakeup()

    async def emit_event(self, event: Any) -> None:
        """launch's coroutine spelling of `emit_event_sync`."""
        self.emit_event_sync(event)

    # -- locals --------------------------------------------------------------------------------
    @property
    def locals(self) -> SimpleNamespace:
        """What the entities being visited may read: `context.locals.event` in a handler's."""
        merged: dict[str, Any] = {}
        for layer in self._locals_stack:
            merged.update(layer)
        return SimpleNamespace(**merged)

    def extend_locals(self, new_locals: dict[str, Any]) -> None:
        self._locals_stack[-1].update(new_locals)

    def get_locals_as_dict(self) -> dict[str, Any]:
        return vars(self.locals)

    def _push_locals(self) -> None:
        self._locals_stack.append({})

    def _pop_locals(self) -> None:
        self._locals_stack.pop()
