"""Clocks, as rclpy.clock.Clock.

A node's clock is a ROSClock: system time, or simulated time while `use_sim_time` is set
(zros.time_source feeds it from /clock). Timers, rates and sleeps run on a clock: on simulated
time they stop while it stands still and speed up with it. On real time they run on the
monotonic clock, so a wall-clock step (NTP) does not make them fire in a burst or stall.
"""
from __future__ import annotations

import threading
import time as _time
from typing import Any, Callable

from zros.duration import Duration
from zros.time import ClockType, Time

__all__ = ['Clock', 'ROSClock', 'ClockType']

# How often a sleep re-checks that its context is still up.
_SLEEP_SLICE_S = 0.1


class Clock:
    """A source of time that timers, rates and sleeps run on.

    :param clock_type: SYSTEM_TIME (wall clock), STEADY_TIME (monotonic) or ROS_TIME (use
        ROSClock for that, which can follow /clock).
    """
    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        self._clock_type = ClockType(clock_type)
        self._sim_time_ns: int | None = None   # simulated time, for a ROSClock whose override is on
        self._sim_epoch = 0                    # bumped when simulated time is switched on or off
        self._changed = threading.Condition()
        self._listeners: list[Callable[[], None]] = []

    @property
    def clock_type(self) -> ClockType:
        """The ClockType this clock reads."""
        return self._clock_type

    def now(self) -> Time:
        """Read the clock.

        :return: A Time of this clock's type: simulated time while a ROSClock follows /clock.
        """
        if self._clock_type == ClockType.STEADY_TIME:
            ns = _time.monotonic_ns()
        elif self._sim_time_ns is not None:
            ns = self._sim_time_ns
        else:
            ns = _time.time_ns()
        return Time(nanoseconds=ns, clock_type=self._clock_type)

    def _schedule_ns(self) -> tuple[int, bool]:
        """(now, simulated): the time timers and rates of this clock are scheduled on."""
        sim = self._sim_time_ns
        return (_time.monotonic_ns(), False) if sim is None else (sim, True)

    def _add_listener(self, listener: Callable[[], None]) -> None:
        """`listener()` runs (on the thread that sets it) after every change of simulated time."""
        with self._changed:
            self._listeners.append(listener)

    def _remove_listener(self, listener: Callable[[], None]) -> None:
        with self._changed:
            if listener in self._listeners:
                self._listeners.remove(listener)

    def sleep_until(self, until: Time, context: Any = None) -> bool:
        """Sleep until this clock reads `until`. False when it woke for another reason: the
        context shut down, or simulated time was switched on or off (the epoch changed)."""
        from zros.context import get_default_context
        from zros.errors import NotInitializedError
        context = context or get_default_context()
        if not context.ok():
            raise NotInitializedError('zros is not initialized (or already shut down)')
        if until.clock_type != self._clock_type:
            raise ValueError("until's clock type does not match this clock's type")
        epoch = self._sim_epoch
        with self._changed:
            while True:
                if not context.ok() or self._sim_epoch != epoch:
                    return False
                remaining = until.nanoseconds - self.now().nanoseconds
                if remaining <= 0:
                    return True
                if self._sim_time_ns is not None:
                    self._changed.wait(_SLEEP_SLICE_S)   # woken by every /clock update
                else:
                    self._changed.wait(min(_SLEEP_SLICE_S, remaining / 1e9))

    def sleep_for(self, rel_time: Duration, context: Any = None) -> bool:
        """Sleep for `rel_time` on this clock (on simulated time, until /clock has moved that far).

        :param rel_time: How long to sleep, a Duration.
        :param context: The context whose shutdown ends the sleep early; the default context if
            ``None``.
        :return: ``True`` if the time passed, ``False`` if the sleep ended early (shutdown, or
            simulated time switched on or off).
        :raises NotInitializedError: If the context is not initialized.
        """
        return self.sleep_until(self.now() + rel_time, context)

    def __repr__(self) -> str:
        return f'Clock(clock_type={self._clock_type.name})'


class ROSClock(Clock):
    """A node's clock: system time, or simulated time from /clock while `use_sim_time` is true.

    zros.time_source sets the simulated time; there is no rcl clock handle behind it.
    """
    def __init__(self) -> None:
        super().__init__(clock_type=ClockType.ROS_TIME)

    @property
    def ros_time_is_active(self) -> bool:
        """Whether the clock reads simulated time (from /clock) rather than system time."""
        return self._sim_time_ns is not None

    def _set_ros_time_override(self, nanoseconds: int | None) -> None:
        """Simulated time is now `nanoseconds` (None: back to system time). Called by
        zros.time_source on Zenoh's thread."""
        with self._changed:
            if (nanoseconds is None) != (self._sim_time_ns is None):
                self._sim_epoch += 1
            self._sim_time_ns = nanoseconds
            self._changed.notify_all()
            listeners = list(self._listeners)
        for listener in listeners:
            listener()
