"""The event side of a launch context (launch.LaunchContext's): the event queue and the handlers
registered on it. The locals a handler's entities see (`context.locals.event`) are the
context's own (zros.launch.locals), which a handler pushes and extends.

LaunchContext inherits it; zros.launch.launch_service drains the queue while the launch runs.
Handlers are offered an event newest first (as in launch), so a user's handler sees an event
before the launch's own.
"""
from __future__ import annotations

import queue
from collections import deque
from typing import Any

__all__ = ['EventDispatch']


class EventDispatch:
    """Queue and handlers. Any thread may emit; one thread (the launch's) drains."""

    def __init__(self) -> None:
        self._event_queue: queue.Queue = queue.Queue()
        self._event_handlers: deque = deque()
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

    def would_handle_event(self, event: Any) -> bool:
        """Whether a registered handler matches `event` (so that emitting it is worth it)."""
        return any(handler.matches(event) for handler in self._event_handlers)

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
