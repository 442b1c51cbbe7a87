"""Opaque handles (rclpy's `node.handle`, `publisher.handle`, `context.handle` ...): the token
that says an entity is still alive, and keeps it alive while someone works with it.

rclpy's handles wrap rcl's C structures; zros has none, so a zros handle stands for the zros
object that owns it (the node, the entity with its Zenoh declaration, the context with its
session) and carries only its lifetime. `with x.handle:` raises InvalidHandle once `x` has been
destroyed, and a destroy that comes while a `with` block holds the handle takes effect when the
last such block ends, so what the block uses is not released under it. Nothing else is behind
a zros handle: code that passes handles to `_rclpy` functions has no equivalent here.
"""
from __future__ import annotations

import threading
from typing import Callable

from zros.errors import InvalidHandle

__all__ = ['Handle', 'HandleOwner']


class Handle:
    """The handle of one zros object, made by that object; users only hold it and use `with`.

    Args:
        name: what the handle stands for, for messages (``"node 'talker'"``).
    """

    def __init__(self, name: str) -> None:
        self._name = name
        self._lock = threading.Lock()
        self._users = 0
        self._valid = True
        self._pending: Callable[[], None] | None = None

    @property
    def valid(self) -> bool:
        """False once the owner asked for its destruction."""
        return self._valid

    def __enter__(self) -> 'Handle':
        """Hold the owner alive for the block.

        Raises:
            InvalidHandle: the owner was destroyed already.
        """
        with self._lock:
            if not self._valid:
                raise InvalidHandle(f'{self._name} has been destroyed')
            self._users += 1
        return self

    def __exit__(self, *exc: object) -> None:
        with self._lock:
            self._users -= 1
            release = self._pending if self._users == 0 else None
            if release is not None:
                self._pending = None
        if release is not None:
            release()

    def destroy_when_not_in_use(self, release: Callable[[], None] | None = None) -> bool:
        """Invalidate the handle and run `release` (the owner's clean-up) now, or when the last
        `with` block holding it ends (on the thread that leaves that block).

        Returns:
            False if the handle was invalid already (`release` is not run again).
        """
        with self._lock:
            if not self._valid:
                return False
            self._valid = False
            if self._users:
                self._pending = release
                return True
        if release is not None:
            release()
        return True

    def __repr__(self) -> str:
        return f'<zros Handle of {self._name}{"" if self._valid else " (destroyed)"}>'


class HandleOwner:
    """Mixin of the objects rclpy gives a `handle` (node, entities, timers, guard conditions):
    the owner creates `_handle` in its constructor and invalidates it when it is destroyed."""

    _handle: Handle

    @property
    def handle(self) -> Handle:
        """rclpy's opaque handle: `with x.handle:` keeps `x` from being released during the
        block, and raises InvalidHandle once `x` is destroyed (see zros.handle)."""
        return self._handle
