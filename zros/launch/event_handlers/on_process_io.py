"""`OnProcessIO` (launch.event_handlers.on_process_io): a process's stdin, stdout or stderr
text, as it comes."""
from __future__ import annotations

from typing import Any, Callable

from zros.launch.errors import LaunchTypeError, Origin
from zros.launch.event_handlers.on_action_event_base import OnActionEventBase
from zros.launch.events.process import ProcessIO
from zros.launch.origin import origin_here

__all__ = ['OnProcessIO']


class OnProcessIO(OnActionEventBase):
    """`OnProcessIO(target_action=node, on_stdin=f, on_stdout=f, on_stderr=f)`: each `f(event)`
    gets the ProcessIO event of its stream (`event.text`, bytes) and may return actions."""

    event, _key, event_type = 'io', 'on_io', ProcessIO   # on_io: the base's slot, unused

    def __init__(self, *, target_action: Any = None, on_stdin: Callable | None = None,
                 on_stdout: Callable | None = None, on_stderr: Callable | None = None,
                 handle_once: bool = False, origin: Origin | None = None) -> None:
        origin = origin or origin_here('OnProcessIO')
        super().__init__(target_action=target_action, handle_once=handle_once, origin=origin, on_io=None)
        self.by_fd: dict[int, Callable | None] = {0: on_stdin, 1: on_stdout, 2: on_stderr}
        for key, function in zip(('on_stdin', 'on_stdout', 'on_stderr'), self.by_fd.values()):
            if function is not None and not callable(function):
                raise LaunchTypeError(origin.with_key(key), f'expected a function, got {type(function).__name__}')

    def handle(self, event: Any, context: Any) -> Any:
        super().handle(event, context)
        function = self.by_fd.get(event.fd)
        return None if function is None else function(event)
