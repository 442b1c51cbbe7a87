"""`EventHandler` (launch.EventHandler): a matcher picking events, and the entities to visit
when one comes.

The launch's event queue (zros.launch.event_dispatch, driven by zros.launch.launch_service)
offers each event to the handlers registered on the context; `handle(event, context)` makes the
event visible as `context.locals.event` to what the handler returns, and a `handle_once`
handler unregisters itself on its first event.
"""
from __future__ import annotations

from typing import Any, Callable

__all__ = ['BaseEventHandler', 'EventHandler']


class BaseEventHandler:
    """What every handler does: match an event, put it in the context's locals, unregister
    itself when `handle_once`. Subclasses say what `handle` returns."""

    def __init__(self, *, matcher: Callable[[Any], bool], handle_once: bool = False) -> None:
        self.matcher = matcher
        self.handle_once = handle_once

    def matches(self, event: Any) -> bool:
        return bool(self.matcher(event))

    def describe(self) -> tuple[str, list]:
        """(what it is, the entities it may return), as launch's `--print` uses it."""
        return f'{type(self).__name__}(matcher={self.matcher!r}, handle_once={self.handle_once})', []

    def handle(self, event: Any, context: Any) -> Any:
        context.extend_locals({'event': event})
        if self.handle_once:
            context.unregister_event_handler(self)
        return None


class EventHandler(BaseEventHandler):
    """`EventHandler(matcher=f(event), entities=[...], handle_once=False)`: visit `entities`
    (an entity or a list of them) for each event `matcher` accepts."""

    def __init__(self, *, matcher: Callable[[Any], bool], entities: Any = None, handle_once: bool = False) -> None:
        super().__init__(matcher=matcher, handle_once=handle_once)
        self.entities = entities

    def handle(self, event: Any, context: Any) -> Any:
        super().handle(event, context)
        return self.entities
