"""Callback groups: which callbacks a multi-threaded executor may run at the same time."""
from __future__ import annotations

import threading

__all__ = ['CallbackGroup', 'MutuallyExclusiveCallbackGroup', 'ReentrantCallbackGroup']


class CallbackGroup:
    """Base: decides whether an entity's callback may start now.

    The executor asks `can_execute(entity)` before it takes a due timer, and brackets every
    callback with `try_enter(entity)` / `leave(entity)`. A group of your own (rclpy's extension
    point: a throttling group, say) implements rclpy's three methods, `can_execute`,
    `beginning_execution` and `ending_execution`, which the bracket calls. The entity is the
    timer, subscription, service, client or guard condition, or None when a suspended `async
    def` callback leaves the group.
    """

    def try_enter(self, entity: object = None) -> bool:
        return bool(self.beginning_execution(entity))

    def leave(self, entity: object = None) -> None:
        self.ending_execution(entity)

    def can_execute(self, entity: object = None) -> bool:
        raise NotImplementedError

    def beginning_execution(self, entity: object = None) -> bool:
        """Permission to run `entity`'s callback now (taken until `ending_execution`)."""
        raise NotImplementedError

    def ending_execution(self, entity: object = None) -> None:
        raise NotImplementedError


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    """One callback of the group at a time: a node's default, so single-threaded code is safe."""

    def __init__(self) -> None:
        self._busy = False
        self._lock = threading.Lock()

    def try_enter(self, entity: object = None) -> bool:
        with self._lock:
            if self._busy:
                return False
            self._busy = True
            return True

    def leave(self, entity: object = None) -> None:
        with self._lock:
            self._busy = False

    def can_execute(self, entity: object = None) -> bool:
        return not self._busy


class ReentrantCallbackGroup(CallbackGroup):
    """Any number of the group's callbacks may run in parallel."""

    def try_enter(self, entity: object = None) -> bool:
        return True

    def leave(self, entity: object = None) -> None:
        pass

    def can_execute(self, entity: object = None) -> bool:
        return True
