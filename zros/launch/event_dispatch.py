"""The event side of a launch context (launch.LaunchContext's): the event queue, the handlers
registered on it, and the locals a handler's entities see (`context.locals.event`).

LaunchContext inherits it; zros.launch.launch_service drains the queue while the launch runs.
Handlers are offered an event newest first (as in launch), so a user's handler sees an event
before the launch's own.
"""
from __future__ import annotations

import queue
from collections import deque
from typing import Any

__all__ = ['EventDispatch', 'Locals']


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

    # -- locals --------------------------------------------------------------------------------
    @property
    def locals(self) -> 'Locals':
        """What the entities being visited may read (`context.locals.event` in a handler's);
        read-only: `extend_locals` is the way in."""
        return Locals(self.get_locals_as_dict())

    def extend_locals(self, new_locals: dict[str, Any]) -> None:
        self._locals_stack[-1].update(new_locals)

    def get_locals_as_dict(self) -> dict[str, Any]:
        merged: dict[str, Any] = {}
        for layer in self._locals_stack:
            merged.update(layer)
        return merged

    def _push_locals(self) -> None:
        """A layer whose names hide the ones below until `_pop_locals`."""
        self._locals_stack.append({})

    def _pop_locals(self) -> None:
        if len(self._locals_stack) == 1:
            raise RuntimeError('_pop_locals() without a _push_locals()')
        self._locals_stack.pop()


class Locals:
    """A read-only attribute view of a context's locals."""

    __slots__ = ('_values',)

    def __init__(self, values: dict[str, Any]) -> None:
        object.__setattr__(self, '_values', values)

    def __getattr__(self, name: str) -> Any:
        try:
            return self._values[name]
        except KeyError:
            raise AttributeError(f"context.locals has no '{name}'") from None

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError('context.locals is read-only; use context.extend_locals()')
