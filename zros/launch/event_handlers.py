"""Event handlers (launch.event_handlers): actions to run when a process starts or exits, or
when the launch shuts down.

`RegisterEventHandler(OnProcessExit(target_action=node, on_exit=[...]))`. The handler's actions
are resolved with the rest of the launch (so their errors stop it before anything starts) and
carried out by the supervisor when the event happens. `on_exit` / `on_start` may instead be a
function `f(event, context)` returning actions, as in launch; it runs when the event happens,
with `event.returncode`, `event.pid`, `event.action`, `event.process_name` and `event.cmd`.
`OnShutdown(on_shutdown=...)` runs when the launch starts shutting down (Ctrl-C, a Shutdown
event, a process with `on_exit=Shutdown()`); its function receives launch.events.Shutdown
(`event.reason`), and what it returns is logged (LogInfo) while the processes stop.
"""
from __future__ import annotations

from typing import Any, Callable, NamedTuple

from zros.launch.errors import LaunchFileError, Origin
from zros.launch.files import module_getattr
from zros.launch.origin import origin_here

__all__ = ['OnProcessStart', 'OnProcessExit', 'OnShutdown', 'ProcessEvent']

__getattr__ = module_getattr(__name__)


class ProcessEvent(NamedTuple):
    """What a handler function receives (launch's ProcessStarted / ProcessExited)."""

    action: Any
    process_name: str
    pid: int
    cmd: list
    returncode: int | None    # None for a start

    @property
    def name(self) -> str:
        return self.process_name


class _ProcessEventHandler:
    """A process event (`event`), a target (an action, or None for every process), and what
    to do: a list of actions or a function of (event, context)."""

    event = ''
    _key = ''

    def __init__(self, *, target_action: Any = None, handler: Any, origin: Origin | None = None) -> None:
        from zros.launch.action import Action
        self.origin = origin or origin_here(type(self).__name__)
        if target_action is not None and not isinstance(target_action, Action):
            raise LaunchFileError(self.origin.with_key('target_action'),
                                  f'expected the action of a process (ExecuteProcess, Node), '
                                  f'got {type(target_action).__name__}')
        self.target_action = target_action
        self.function: Callable | None = None
        self.actions: list = []
        if callable(handler):
            self.function = handler
        else:
            from zros.launch.actions.group import check_actions
            self.actions = check_actions(handler, self.origin.with_key(self._key))

    def describe(self) -> str:
        return type(self).__name__

    def transition_filter(self, context: Any) -> Any:
        """Which lifecycle steps the handler fires on (OnStateTransition's); None for the others."""
        return None


class OnProcessStart(_ProcessEventHandler):
    """`OnProcessStart(target_action=node, on_start=[...] or f(event, context))`."""

    event, _key = 'start', 'on_start'

    def __init__(self, *, target_action: Any = None, on_start: Any, origin: Origin | None = None) -> None:
        super().__init__(target_action=target_action, handler=on_start, origin=origin or origin_here('OnProcessStart'))


class OnProcessExit(_ProcessEventHandler):
    """`OnProcessExit(target_action=node, on_exit=[...] or f(event, context))`."""

    event, _key = 'exit', 'on_exit'

    def __init__(self, *, target_action: Any = None, on_exit: Any, origin: Origin | None = None) -> None:
        super().__init__(target_action=target_action, handler=on_exit, origin=origin or origin_here('OnProcessExit'))


class OnShutdown(_ProcessEventHandler):
    """`OnShutdown(on_shutdown=[...] or f(event, context))`: when the launch shuts down."""

    event, _key = 'shutdown', 'on_shutdown'

    def __init__(self, *, on_shutdown: Any, origin: Origin | None = None, **_: Any) -> None:
        super().__init__(handler=on_shutdown, origin=origin or origin_here('OnShutdown'))
