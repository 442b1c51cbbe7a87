"""Timers: periodic callbacks run by the executor (the first call one period after creation)."""
from __future__ import annotations

import threading
import time
from typing import Any, Callable

__all__ = ['Timer', 'Rate', 'timer_lists_changed', 'timer_lists_version']

# Bumped whenever a node gains or loses a timer, so executors can keep their list of timers
# instead of collecting it before every callback.
_timer_lists_version = 0


def timer_lists_changed() -> None:
    global _timer_lists_version
    _timer_lists_version += 1


def timer_lists_version() -> int:
    return _timer_lists_version


class Timer:
    """Made by `Node.create_timer`. Missed periods are skipped, not run in a burst (as rcl)."""

    def __init__(self, callback: Callable[[], Any], callback_group: Any, timer_period_ns: int,
                 clock: Any = None, *, node: Any = None, autostart: bool = True) -> None:
        if timer_period_ns <= 0:
            raise ValueError('timer period must be > 0')
        self.callback = callback
        self.callback_group = callback_group
        self._clock = clock
        self._node = node
        self._period_ns = int(timer_period_ns)
        self._lock = threading.Lock()
        self._last_call_ns = time.monotonic_ns()
        self._next_ns: int | None = self._last_call_ns + self._period_ns if autostart else None
        self._canceled = not autostart
        self._destroyed = False

    @property
    def timer_period_ns(self) -> int:
        return self._period_ns

    @timer_period_ns.setter
    def timer_period_ns(self, value: int) -> None:
        self._period_ns = int(value)
        self.reset()

    @property
    def clock(self) -> Any:
        return self._clock

    def _due_ns(self) -> int | None:
        return None if self._canceled else self._next_ns

    def _claim(self, now_ns: int) -> bool:
        """The executor takes one due call; advance the schedule past `now_ns`."""
        with self._lock:
            if self._canceled or self._next_ns is None or self._next_ns > now_ns:
                return False
            self._next_ns += self._period_ns
            if self._next_ns <= now_ns:
                self._next_ns = now_ns + self._period_ns
            self._last_call_ns = now_ns
            return True

    def _execute(self) -> None:
        self.callback()

    def cancel(self) -> None:
        with self._lock:
            self._canceled = True

    def is_canceled(self) -> bool:
        return self._canceled

    def reset(self) -> None:
        with self._lock:
            self._canceled = False
            self._next_ns = time.monotonic_ns() + self._period_ns
        if self._node is not None and self._node._executor is not None:
            self._node._executor.wake()

    def is_ready(self) -> bool:
        due = self._due_ns()
        return due is not None and due <= time.monotonic_ns()

    def time_since_last_call(self) -> int:
        return time.monotonic_ns() - self._last_call_ns

    def time_until_next_call(self) -> int | None:
        due = self._due_ns()
        return None if due is None else max(0, due - time.monotonic_ns())

    def destroy(self) -> None:
        self.cancel()
        self._destroyed = True


class Rate:
    """`node.create_rate(hz)`: `sleep()` keeps a loop at a fixed frequency.

    Unlike rclpy's, it needs no executor spinning in another thread: it sleeps on the
    monotonic clock, so `while ok(): ...; rate.sleep()` works in a plain script.
    """

    def __init__(self, frequency: float) -> None:
        if frequency <= 0:
            raise ValueError('rate frequency must be > 0')
        self._period = 1.0 / frequency
        self._next = time.monotonic() + self._period
        self._destroyed = False

    def sleep(self) -> None:
        now = time.monotonic()
        if self._next > now:
            time.sleep(self._next - now)
            self._next += self._period
        else:
            self._next = now + self._period

    def destroy(self) -> None:
        self._destroyed = True
