"""Futures, as rclpy.task.Future: completed by one thread, awaited or polled by another.

Done callbacks run on an executor when the future knows one: the executor it was given, or
the executor of its node at the moment it completes (rclpy code often sends a request before it
starts spinning). Only a future with neither runs its callbacks in the completing thread.
"""
from __future__ import annotations

import threading
from typing import Any, Callable

__all__ = ['Future']


class Future:
    def __init__(self, *, executor: Any = None, node: Any = None) -> None:
        self._state = 'pending'  # pending | done | cancelled
        self._result: Any = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[['Future'], None]] = []
        self._lock = threading.Lock()
        self._done_event = threading.Event()
        self._executor = executor
        self._node = node

    def done(self) -> bool:
        return self._state != 'pending'

    def cancelled(self) -> bool:
        return self._state == 'cancelled'

    def cancel(self) -> None:
        self._finish('cancelled', None, None)

    def result(self) -> Any:
        """The result; raises the stored exception; None while pending (as rclpy)."""
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        return self._exception

    def set_result(self, result: Any) -> None:
        self._finish('done', result, None)

    def set_exception(self, exception: BaseException) -> None:
        self._finish('done', None, exception)

    def _finish(self, state: str, result: Any, exception: BaseException | None) -> None:
        with self._lock:
            if self._state != 'pending':
                return
            self._state, self._result, self._exception = state, result, exception
            callbacks, self._callbacks = self._callbacks, []
        self._done_event.set()
        for callback in callbacks:
            self._schedule(callback)
        executor = self._current_executor()
        if executor is not None:
            executor.wake()

    def _current_executor(self) -> Any:
        if self._executor is not None:
            return self._executor
        return getattr(self._node, '_executor', None)

    def _schedule(self, callback: Callable[['Future'], None]) -> None:
        executor = self._current_executor()
        if executor is not None:
            executor.create_task(callback, self)
        else:
            callback(self)

    def add_done_callback(self, callback: Callable[['Future'], None]) -> None:
        with self._lock:
            if self._state == 'pending':
                self._callbacks.append(callback)
                return
        self._schedule(callback)

    def _set_executor(self, executor: Any) -> None:
        self._executor = executor

    def wait(self, timeout: float | None = None) -> bool:
        """Block this thread until done (not part of rclpy; used by blocking helpers)."""
        return self._done_event.wait(timeout)

    def __await__(self):
        while not self.done():
            yield
        return self.result()
