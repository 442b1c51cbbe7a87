"""The handler shape OnProcessStart, OnProcessExit, OnExecutionComplete ... share (launch's
OnActionEventBase): one kind of event, an optional target, and what to do.

The target is an action (events of that action only), a function of the action (events of the
actions it accepts) or None (every such event). What to do is a list of actions, resolved with
the rest of the launch by `zros launch` (so their errors stop it before anything starts), or a
function `f(event, context)` returning actions, called when the event happens.
"""
from __future__ import annotations

from typing import Any, Callable

from zros.launch.errors import LaunchTypeError, Origin
from zros.launch.event_handler import BaseEventHandler
from zros.launch.origin import origin_here

__all__ = ['OnActionEventBase', 'target_matches']


def target_matches(target: Any, action: Any) -> bool:
    """Whether a handler aimed at `target` takes the events of `action`: every action's when
    `target` is None; a function (anything callable, as launch decides) is asked; an action
    matches itself only."""
    if target is None:
        return True
    if callable(target):
        return bool(target(action))
    return action is target


class OnActionEventBase(BaseEventHandler):
    """Subclasses set `event_type` (the launch event class), `event` (the supervisor's name for
    it: 'start', 'exit', 'shutdown', 'transition') and `_key` (the keyword of what to do:
    `OnProcessExit(target_action=node, on_exit=[...])`)."""

    event = ''
    _key = ''
    event_type: type = object

    def __init__(self, *, target_action: Any = None, handle_once: bool = False, origin: Origin | None = None,
                 **what_to_do: Any) -> None:
        """`what_to_do` is the one keyword the subclass names in `_key` (`on_exit=...`); any
        other keyword is a TypeError, as a misspelt keyword argument is in Python."""
        from zros.launch.action import Action
        from zros.launch.actions.group import check_actions
        name = type(self).__name__
        self.origin = origin or origin_here(name)
        if set(what_to_do) != {self._key}:
            wrong = sorted(set(what_to_do) - {self._key})
            raise TypeError(f"{name}() got an unexpected keyword argument '{wrong[0]}'" if wrong
                            else f"{name}() missing 1 required keyword-only argument: '{self._key}'")
        if target_action is not None and not isinstance(target_action, Action) and not callable(target_action):
            raise LaunchTypeError(self.origin.with_key('target_action'),
                                  f'expected the action of a process (ExecuteProcess, Node) or a function '
                                  f'of an action, got {type(target_action).__name__}')
        super().__init__(matcher=self._matches_event, handle_once=handle_once)
        self.target_action = target_action
        self.function: Callable | None = None
        self.actions: list = []
        handler = what_to_do[self._key]
        if callable(handler) and not isinstance(handler, Action):
            self.function = handler
        else:
            self.actions = check_actions(handler, self.origin.with_key(self._key))

    def _matches_event(self, event: Any) -> bool:
        return isinstance(event, self.event_type) and self.matches_action(getattr(event, 'action', None))

    def matches_action(self, action: Any) -> bool:
        """Whether events of `action` are this handler's."""
        return target_matches(self.target_action, action)

    def handle(self, event: Any, context: Any) -> Any:
        super().handle(event, context)
        if self.function is not None:
            return self.function(event, context)
        return self.actions

    def describe(self) -> Any:
        return type(self).__name__

    def transition_filter(self, context: Any) -> Any:
        """Which lifecycle steps the handler fires on (OnStateTransition's); None for the others."""
        return None
