"""Guard conditions (rclpy.guard_condition.GuardCondition): a way for any thread to have a
callback run on a node's executor.

`trigger()` may be called from any thread, as often as it likes: the callback runs once on the
executor for the triggers that came before it ran (a guard condition is a flag, not a queue).
A trigger while the node is not being spun waits for the executor that spins it next.
"""
from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any, Callable

from zros.handle import Handle, HandleOwner

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['GuardCondition']


class GuardCondition(HandleOwner):
    """Made by `Node.create_guard_condition(callback, callback_group=None)`."""

    def __init__(self, callback: Callable[[], Any] | None, callback_group: Any, *, node: 'Node') -> None:
        self.callback = callback
        self.callback_group = callback_group
        self._node = node
        self._lock = threading.Lock()
        self._triggered = False
        self._destroyed = False
        self._handle = Handle('guard condition')

    def trigger(self) -> None:
        if self._destroyed:
            raise RuntimeError('guard condition has been destroyed')
        with self._lock:
            if self._triggered:
                return
            self._triggered = True
        executor = self._node._executor
        if executor is not None:
            executor._enqueue(self)

    def _has_work(self) -> bool:
        return self._triggered and not self._destroyed

    # Executor thread.
    def _execute(self) -> Any:
        with self._lock:
            if not self._triggered or self._destroyed:
                return None
            self._triggered = False
        return self.callback() if self.callback is not None else None

    def destroy(self) -> None:
        self._destroyed = True
        self._handle.destroy_when_not_in_use()
