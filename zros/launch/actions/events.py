"""`RegisterEventHandler`: run actions when a process starts or exits, the launch shuts down,
or a lifecycle node goes through a transition the launch requested; or register any other
launch.EventHandler on the running launch's event queue. `UnregisterEventHandler` takes such
an event-queue handler off again."""
from __future__ import annotations

from typing import Any

from zros.launch.action import Action, EndCapture
from zros.launch.actions.scope import scoped
from zros.launch.errors import LaunchTypeError
from zros.launch.event_handler import BaseEventHandler
from zros.launch.event_handlers import OnProcessExit, OnProcessStart, OnShutdown
from zros.launch.plan import EventHandlerEffect

__all__ = ['RegisterEventHandler', 'UnregisterEventHandler']


class RegisterEventHandler(Action):
    """`RegisterEventHandler(OnProcessExit(target_action=..., on_exit=[...]))` (or OnProcessStart,
    OnShutdown, launch_ros's OnStateTransition).

    A list of actions is resolved now, in a scope of its own (like a timer's), and carried out
    when the event happens; a handler function runs then, in a copy of the context as it is
    here, and so does a list holding an OpaqueFunction, whose function must not run before its
    event (Nav2's `OnShutdown(on_shutdown=[OpaqueFunction(function=remove_temp_file)])`). Python
    only: ROS 2's YAML format has no tag for it.
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
        """The handler's actions (an EventHandler's `entities`), for zros's static walks."""
        handler = self.event_handler
        entities = getattr(handler, 'actions', None)
        if entities is None:
            entities = getattr(handler, 'entities', None)
        if entities is None:
            return []
        return [entities] if not isinstance(entities, (list, tuple)) else list(entities)

    def describe_sub_entities(self) -> list[Action]:
        """None: the handler's actions run only if its event happens (launch's description)."""
        return []

    def describe_conditional_sub_entities(self) -> list[tuple[str, list[Action]]]:
        return [(f'on {type(self.event_handler).__name__}', self.sub_actions())]

    def execute(self, context: Any) -> list[Action]:
        handler = self.event_handler
        if not self._supervised():
            context.register_event_handler(handler)
            return []
        function = handler.function if handler.function is not None else _deferred_actions(handler)
        if function is not None:
            from zros.launch.description import Deferred
            deferred = Deferred(function, context.snapshot(), handler.origin)
            context.emit(EventHandlerEffect(handler.event, handler.target_action, [], deferred, handler.origin))
            return []
        transition = handler.transition_filter(context)
        context.begin_capture()

        def wrap(effects: list) -> EventHandlerEffect:
            return EventHandlerEffect(handler.event, handler.target_action, effects, None, handler.origin, transition)
        return [*scoped(handler.actions, self.origin),
                EndCapture(origin=self.origin, wrap=wrap)]


def _deferred_actions(handler: Any) -> Any:
    """A handler function returning the handler's actions, if they hold an OpaqueFunction (its
    user code runs when the event happens, not while the launch is planned); else None."""
    from zros.launch.actions.opaque import OpaqueFunction
    actions = handler.actions if isinstance(handler.actions, (list, tuple)) else [handler.actions]
    if not isinstance(handler, (OnProcessStart, OnProcessExit, OnShutdown)) or \
            not any(isinstance(action, OpaqueFunction) for action in actions):
        return None

    def actions_on_event(event: Any, context: Any) -> list:
        return list(actions)
    return actions_on_event


class UnregisterEventHandler(Action):
    """`UnregisterEventHandler(handler)`: stop offering events to a handler that
    RegisterEventHandler put on the event queue (a launch.EventHandler, OnExecutionComplete,
    OnIncludeLaunchDescription, ...). Executing it for a handler that is not registered raises
    ValueError, as launch does. The process, shutdown and lifecycle handlers are the
    supervisor's, fixed for the whole launch: unregistering one is an error at this point.
    """

    def __init__(self, event_handler: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not isinstance(event_handler, BaseEventHandler):
            raise LaunchTypeError(self.origin.with_key('event_handler'),
                                  f'expected an event handler, got {type(event_handler).__name__}')
        self.event_handler = event_handler

    def execute(self, context: Any) -> None:
        if RegisterEventHandler(self.event_handler, origin=self.origin)._supervised():
            raise LaunchTypeError(self.origin.with_key('event_handler'),
                                  f'{type(self.event_handler).__name__} handlers stay registered for the whole '
                                  'launch in zros (only event-queue handlers such as launch.EventHandler '
                                  'can be unregistered)')
        context.unregister_event_handler(self.event_handler)
