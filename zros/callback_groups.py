"""Callback groups: which callbacks a multi-threaded executor may run at the same time."""
from __future__ import annotations

import threading
import weakref

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

    def has_entity(self, entity: object) -> bool:
        """Whether `entity` (a timer, subscription, service, client ...) runs in this group: the
        group its node gave it when it was created, or one it was added to with `add_entity`."""
        if getattr(entity, 'callback_group', None) is self:
            return True
        added = self.__dict__.get('_added')
        return added is not None and entity in added

    def add_entity(self, entity: object) -> None:
        """Count `entity` in this group (rclpy's registration; a Waitable does it for itself).

        :param entity: Any object that can be weakly referenced; the group does not keep it alive.
        """
        self.__dict__.setdefault('_added', weakref.WeakSet()).add(entity)

    def try_enter(self, entity: object = None) -> bool:
        """Take the group for `entity`'s callback if it may run now; the executor calls this.

        :param entity: The entity whose callback would run.
        :return: ``True`` if the callback may run; the executor then calls `leave` when it ends.
        """
        return bool(self.beginning_execution(entity))

    def leave(self, entity: object = None) -> None:
        """Give the group back after `entity`'s callback ended; the executor calls this.

        :param entity: The entity whose callback ended, or ``None`` for a suspended task.
        """
        self.ending_execution(entity)

    def can_execute(self, entity: object = None) -> bool:
        """Tell whether `entity`'s callback could start now, without taking the group.

        :param entity: The entity to ask about.
        :return: ``True`` if it could run.
        """
        raise NotImplementedError

    def beginning_execution(self, entity: object = None) -> bool:
        """Permission to run `entity`'s callback now (taken until `ending_execution`)."""
        raise NotImplementedError

    def ending_execution(self, entity: object = None) -> None:
        """Release what `beginning_execution` took for `entity`.

        :param entity: The entity whose callback ended.
        """
        raise NotImplementedError


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    """One callback of the group at a time: a node's default, so single-threaded code is safe."""

    def __init__(self) -> None:
        self._busy = False
        self._lock = threading.Lock()

    def try_enter(self, entity: object = None) -> bool:
        """Take the group if no callback of it runs.

        :param entity: Unused: every entity of the group shares one slot.
        :return: ``True`` if the group was free and is now taken.
        """
        with self._lock:
            if self._busy:
                return False
            self._busy = True
            return True

    def leave(self, entity: object = None) -> None:
        """Free the group for its next callback.

        :param entity: Unused.
        """
        with self._lock:
            self._busy = False

    def can_execute(self, entity: object = None) -> bool:
        """Tell whether the group is free.

        :param entity: Unused.
        :return: ``True`` if no callback of the group runs.
        """
        return not self._busy

    # rclpy's names for the bracket, which this group implements directly.
    beginning_execution = try_enter
    ending_execution = leave


class ReentrantCallbackGroup(CallbackGroup):
    """Any number of the group's callbacks may run in parallel."""

    def try_enter(self, entity: object = None) -> bool:
        """Always admit the callback.

        :param entity: Unused.
        :return: ``True``.
        """
        return True

    def leave(self, entity: object = None) -> None:
        """Nothing to give back.

        :param entity: Unused.
        """
        pass

    def can_execute(self, entity: object = None) -> bool:
        """Always allowed.

        :param entity: Unused.
        :return: ``True``.
        """
        return True

    beginning_execution = try_enter
    ending_execution = leave
