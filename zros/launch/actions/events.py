"""`RegisterEventHandler`: run actions when a process starts or exits, the launch shuts down,
or a lifecycle node goes through a transition the launch requested; or register any other
launch.EventHandler on the running launch's event queue."""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, EndCapture
from zros.launch.actions.scope import scoped
from zros.launch.errors import LaunchTypeError
from zros.launch.event_handler import BaseEventHandler
from zros.launch.event_handlers import OnProcessExit, OnProcessStart, OnShutdown
from zros.launch.plan import EventHandlerEffect

__all__ = ['RegisterEventHandler']


class RegisterEventHandler(Action):
    """`RegisterEventHandler(OnProcessExit(target_action=..., on_exit=[...]))` (or OnProcessStart,
    OnShutdown, launch_ros's OnStateTransition).

    A list of actions is resolved now, in a scope of its own (like a timer's), and carried out
    when the event happens; a handler function runs then, in a copy of the context as it is
    here. Python only: ROS 2's YAML format has no tag for it.
    """

    def __init__(self, event_handler: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not isinstance(event_handler, BaseEventHandler):
            raise LaunchTypeError(self.origin.with_key('event_handler'),
                                  f'expected an event handler (launch.EventHandler, OnProcessExit, ...), '
                                  f'got {type(event_handler).__name__}')
        self.event_handler = event_handler

    def _supervised(self) -> bool:
        """Whether the supervisor carries this handler out (the process, shutdown and lifecycle
        handlers); any other is registered on the context's event queue when reached."""
        from zros.launch.lifecycle import OnStateTransition
        return isinstance(self.event_handler, (OnProcessStart, OnProcessExit, OnShutdown, OnStateTransition))

    def sub_actions(self) -> list[Action]:
        return list(getattr(self.event_handler, 'actions', []))

    def execute(self, context: Any) -> list[Action]:
        handler = self.event_handler
        if not self._supervised():
            context.register_event_handler(handler)
            return []
        if handler.function is not None:
            from zros.launch.description import Deferred
            deferred = Deferred(handler.function, context.snapshot(), handler.origin)
            context.emit(EventHandlerEffect(handler.event, handler.target_action, [], deferred, handler.origin))
            return []
        transition = handler.transition_filter(context)
        context.begin_capture()

        def wrap(effects: list) -> EventHandlerEffect:
            return EventHandlerEffect(handler.event, handler.target_action, effects, None, handler.origin, transition)
        return [*scoped(handler.actions, self.origin),
                EndCapture(origin=self.origin, wrap=wrap)]
