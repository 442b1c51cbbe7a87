"""`OnShutdown` (launch.event_handlers.on_shutdown): when the launch starts shutting down
(Ctrl-C, a Shutdown event, a process with `on_exit=Shutdown()`).

Its function receives launch.events.Shutdown (`event.reason`); under `zros launch` what it
returns is logged (LogInfo) while the processes stop.
"""
from __future__ import annotations

from typing import Any

from zros.launch.errors import Origin
from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.shutdown import Shutdown
from zros.launch.origin import origin_here

__all__ = ['OnShutdown']


class OnShutdown(OnActionEventBase):
    """`OnShutdown(on_shutdown=[...] or f(event, context))`."""

    event, _key, event_type = 'shutdown', 'on_shutdown', Shutdown

    def __init__(self, *, on_shutdown: Any, handle_once: bool = False, origin: Origin | None = None,
                 **_: Any) -> None:
        super().__init__(on_shutdown=on_shutdown, handle_once=handle_once, origin=origin or origin_here('OnShutdown'))
        self.given = on_shutdown

    def handle(self, event: Any, context: Any) -> Any:
        """What the handler was given, as given (an action stays one action), or what its
        function returns."""
        result = super().handle(event, context)
        return result if self.function is not None else self.given
