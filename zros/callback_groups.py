"""Callback groups: which callbacks a multi-threaded executor may run at the same time."""
from __future__ import annotations

import threading

__all__ = ['CallbackGroup', 'MutuallyExclusiveCallbackGroup', 'ReentrantCallbackGroup']


class CallbackGroup:
    """Base: decides whether an entity's callback may start now (`try_enter` / `leave`)."""

    def try_enter(self) -> bool:
        raise NotImplementedError

    def leave(self) -> None:
        raise NotImplementedError

    def can_execute(self, entity: object = None) -> bool:
        raise NotImplementedError


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    """One callback of the group at a time: a node's default, so single-threaded code is safe."""

    def __init__(self) -> None:
        self._busy = False
        self._lock = threading.Lock()

    def try_enter(self) -> bool:
        with self._lock:
            if self._busy:
                return False
            self._busy = True
            return True

    def leave(self) -> None:
        with self._lock:
            self._busy = False

    def can_execute(self, entity: object = None) -> bool:
        return not self._busy


class ReentrantCallbackGroup(CallbackGroup):
    """Any number of the group's callbacks may run in parallel."""

    def try_enter(self) -> bool:
        return True

    def leave(self) -> None:
        pass

    def can_execute(self, entity: object = None) -> bool:
        return True
