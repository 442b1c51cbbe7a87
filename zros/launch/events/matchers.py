"""`matches_action` (launch.events.matches_action): aim an event at one action."""
from __future__ import annotations

from typing import Any

__all__ = ['ActionMatcher', 'matches_action']


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
