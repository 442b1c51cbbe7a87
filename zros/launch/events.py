"""Events an action can emit (launch.events): `Shutdown`, and `matches_action` to aim an event
at one action (launch_ros's lifecycle `ChangeState` takes it as its `lifecycle_node_matcher`)."""
from __future__ import annotations

from typing import Any

from zros.launch.files import module_getattr

__all__ = ['Shutdown', 'matches_action', 'ActionMatcher']

__getattr__ = module_getattr(__name__)


class Shutdown:
    """`EmitEvent(event=Shutdown(reason='...'))` stops the whole launch."""

    def __init__(self, *, reason: Any = None) -> None:
        self.reason = reason

    def __repr__(self) -> str:
        return f'<Shutdown reason={self.reason!r}>'


class ActionMatcher:
    """What `matches_action(action)` returns: called with an action, whether it is that one
    (as launch's lambda). zros keeps the target so the launch can check it and `--print` it."""

    def __init__(self, target: Any) -> None:
        self.target = target

    def __call__(self, action: Any) -> bool:
        return action is self.target

    def __repr__(self) -> str:
        return f'matches_action({self.target!r})'


def matches_action(target_action: Any) -> ActionMatcher:
    """A matcher for events aimed at `target_action` only."""
    return ActionMatcher(target_action)
