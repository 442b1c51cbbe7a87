"""Timers and rates on a clock (the first timer call one period after creation).

Both schedule on `Clock._schedule_ns()`: simulated time while the clock has it (so with
`use_sim_time` they stop while /clock stands still and speed up with it, as rclpy's), else
the monotonic clock. A switch between the two, or simulated time going backwards (a restarted
simulation, a looping bag), restarts the schedule from the current time.
"""
from __future__ import annotations

import threading
from typing import Any, Callable

from zros.clock import Clock, ClockType
from zros.handle import Handle, HandleOwner

__all__ = ['Timer', 'Rate', 'timer_lists_changed', 'timer_lists_version']

# Bumped whenever a node gains or loses a timer, so executors can keep their list of timers
# instead of collecting it before every callback.
_timer_lists_version = 0


def timer_lists_changed() -> None:
    """Note that some node gained or lost a timer.

    Executors cache the list of timers they watch and rebuild it only when this version moves.
    """
    global _timer_lists_version
    _timer_lists_version += 1


def timer_lists_version() -> int:
    """The version that `timer_lists_changed` bumps.

    :return: A counter that changes whenever any node's set of timers changes.
    """
    return _timer_lists_version


class _Schedule:
    """Next due time of a periodic event on a clock, in that clock's scheduling time."""

    def __init__(self, clock: Clock, period_ns: int, *, running: bool) -> None:
        self.clock = clock
        self.period_ns = int(period_ns)
        self.last_ns, self.sim = clock._schedule_ns()
        self.next_ns: int | None = self.last_ns + self.period_ns if running else None

    def now(self) -> int:
        """Current scheduling time; restarts the schedule if the time base changed."""
        now, sim = self.clock._schedule_ns()
        if sim != self.sim or (sim and now < self.last_ns):
            self.sim, self.last_ns = sim, now
            if self.next_ns is not None:
                self.next_ns = now + self.period_ns
        return now

    def restart(self) -> None:
        self.next_ns = self.now() + self.period_ns

    def advance(self, now: int) -> None:
        """One due call taken at `now`. Missed periods are skipped, not run in a burst, and the
        schedule keeps its phase (as rcl): a timer of 0.5 s whose simulated time jumps from 0 to
        10.04 s calls once, then at 10.5 s."""
        assert self.next_ns is not None, 'advance() is only called on a running schedule'
        if self.next_ns <= now:
            self.next_ns += ((now - self.next_ns) // self.period_ns + 1) * self.period_ns
        self.last_ns = now


class Timer(HandleOwner):
    """Made by `Node.create_timer`."""

    def __init__(self, callback: Callable[[], Any], callback_group: Any, timer_period_ns: int,
                 clock: Clock | None = None, *, node: Any = None, autostart: bool = True) -> None:
        if timer_period_ns <= 0:
            raise ValueError('timer period must be > 0')
        self.callback = callback
        self.callback_group = callback_group
        self._clock = clock if clock is not None else Clock(clock_type=ClockType.STEADY_TIME)
        self._node = node
        self._lock = threading.Lock()
        self._schedule = _Schedule(self._clock, timer_period_ns, running=autostart)
        self._canceled = not autostart
        self._destroyed = False
        self._handle = Handle('timer')

    @property
    def timer_period_ns(self) -> int:
        """The period between two calls, in nanoseconds."""
        return self._schedule.period_ns

    @timer_period_ns.setter
    def timer_period_ns(self, value: int) -> None:
        self._schedule.period_ns = int(value)
        self.reset()

    @property
    def clock(self) -> Clock:
        """The clock the timer is scheduled on (the node's ROS clock unless one was given)."""
        return self._clock

    @property
    def _on_sim_time(self) -> bool:
        """Due by simulated time: the executor is woken by /clock, not by waiting."""
        return self._schedule.sim

    def _remaining_ns(self) -> int | None:
        """Scheduling-time ns until due (<= 0: due now), None when canceled."""
        if self._canceled:
            return None
        schedule = self._schedule
        now = schedule.now()
        return None if schedule.next_ns is None else schedule.next_ns - now

    def _claim(self) -> bool:
        """The executor takes one due call."""
        with self._lock:
            schedule = self._schedule
            now = schedule.now()
            if self._canceled or schedule.next_ns is None or schedule.next_ns > now:
                return False
            schedule.advance(now)
            return True

    def _execute(self) -> Any:
        return self.callback()

    def cancel(self) -> None:
        """Stop calling the callback until `reset()`; the timer stays registered with its node."""
        with self._lock:
            self._canceled = True

    def is_canceled(self) -> bool:
        """Tell whether the timer is cancelled.

        :return: ``True`` after `cancel()` and before the next `reset()`.
        """
        return self._canceled

    def reset(self) -> None:
        """Restart the period from now, and un-cancel the timer.

        The node's executor is woken so that it picks up the new due time at once.
        """
        with self._lock:
            self._canceled = False
            self._schedule.restart()
        if self._node is not None and self._node._executor is not None:
            self._node._executor.wake()

    def is_ready(self) -> bool:
        """Tell whether the timer is due.

        :return: ``True`` when a period has passed since the last call and the timer is not cancelled.
        """
        remaining = self._remaining_ns()
        return remaining is not None and remaining <= 0

    def time_since_last_call(self) -> int:
        """Time since the callback was last due (or since creation or reset).

        :return: Nanoseconds, in the timer's scheduling time (simulated time under use_sim_time).
        """
        return self._schedule.now() - self._schedule.last_ns

    def time_until_next_call(self) -> int | None:
        """Time left until the callback is due.

        :return: Nanoseconds (0 when already due), or ``None`` when the timer is cancelled.
        """
        remaining = self._remaining_ns()
        return None if remaining is None else max(0, remaining)

    def destroy(self) -> None:
        """Cancel the timer for good.

        `Node.destroy_timer` calls this and also drops the timer from the node; prefer that.
        """
        self.cancel()
        self._destroyed = True
        self._handle.destroy_when_not_in_use()


class Rate:
    """`node.create_rate(hz)`: `sleep()` keeps a loop at a fixed frequency on the node's clock.

    Unlike rclpy's it needs no executor spinning in another thread, so `while ok(): ...;
    rate.sleep()` works in a plain script. As rclpy's, `sleep()` raises ROSInterruptException
    once the context is shut down.
    """

    def __init__(self, frequency: float, clock: Clock | None = None, *, context: Any = None) -> None:
        from zros.context import get_default_context
        if frequency <= 0:
            raise ValueError('rate frequency must be > 0')
        self._clock = clock if clock is not None else Clock(clock_type=ClockType.STEADY_TIME)
        self._schedule = _Schedule(self._clock, int(1e9 / frequency), running=True)
        self._context = context or get_default_context()
        self._destroyed = False
        self._pacer: Any = None   # the node's timer of this period (Node.create_rate), if any

    def sleep(self) -> None:
        """Block until the next period of the rate begins.

        Unlike a timer, a rate is waited on in the calling thread, so call it from a thread other
        than the one spinning the node (as in rclpy).

        :raises RuntimeError: If the rate has been destroyed.
        :raises ROSInterruptException: If the context shuts down while sleeping.
        """
        from zros.exceptions import ROSInterruptException
        if self._destroyed:
            raise RuntimeError('Rate cannot sleep because it has been destroyed')
        schedule = self._schedule
        clock = self._clock
        with clock._changed:
            while True:
                if not self._context.ok():
                    raise ROSInterruptException()
                if self._destroyed:
                    raise RuntimeError('Rate cannot sleep because it has been destroyed')
                now = schedule.now()
                assert schedule.next_ns is not None   # a rate's schedule always runs
                remaining = schedule.next_ns - now
                if remaining <= 0:
                    break
                # Simulated time: woken by each /clock update; real time: by the deadline.
                clock._changed.wait(0.1 if schedule.sim else min(0.1, remaining / 1e9))
        schedule.advance(now)

    def destroy(self) -> None:
        """Make further `sleep()` calls fail and take the rate's timer off its node.

        A loop that makes a rate per run (a navigation server's goal loop) destroys it when it
        ends; the node's timer must go with it, or every run leaves one more timer waking the
        executor. Calling it twice is harmless; `Node.destroy_rate` calls it too.
        """
        self._destroyed = True
        pacer, self._pacer = self._pacer, None
        if pacer is not None and pacer._node is not None:
            pacer._node.destroy_timer(pacer)
