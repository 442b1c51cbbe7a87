"""Futures, as rclpy.task.Future: completed by one thread, awaited or polled by another.

Done callbacks run in the thread that completes the future, unless an executor is attached
(`_set_executor`), in which case they are scheduled on it so user code stays on executor
threads.
"""
from __future__ import annotations

import threading
from typing import Any, Callable

__all__ = ['Future']


class Future:
    def __init__(self, *, executor: Any = None) -> None:
        self._state = 'pending'  # pending | done | cancelled
        self._result: Any = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[['Future'], None]] = []
        self._lock = threading.Lock()
        self._done_event = threading.Event()
        self._executor = executor

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
        if self._executor is not None:
            self._executor.wake()

    def _schedule(self, callback: Callable[['Future'], None]) -> None:
        if self._executor is not None:
            self._executor.create_task(callback, self)
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
