"""Clocks, as rclpy.clock.Clock.

A node's clock is a ROSClock: system time, or simulated time while `use_sim_time` is set
(zros.time_source feeds it from /clock). Timers, rates and sleeps run on a clock: on simulated
time they stop while it stands still and speed up with it. On real time they run on the
monotonic clock, so a wall-clock step (NTP) does not make them fire in a burst or stall.
"""
from __future__ import annotations

import enum
import threading
import time as _time
from typing import Any, Callable

from zros.duration import Duration
from zros.time import ClockType, Time

__all__ = ['Clock', 'ROSClock', 'ClockType', 'ClockChange', 'JumpThreshold', 'TimeJump', 'JumpHandle']


class ClockChange(enum.IntEnum):
    """What a time jump did to a ROSClock's source (rcl's rcl_clock_change_t)."""
    ROS_TIME_NO_CHANGE = 1      # simulated time moved
    ROS_TIME_ACTIVATED = 2      # the clock switched from system to simulated time
    ROS_TIME_DEACTIVATED = 3    # and back
    SYSTEM_TIME_NO_CHANGE = 4


class JumpThreshold:
    """When a jump callback fires: a forward jump of at least `min_forward`, a backward one of at
    least `min_backward` (a negative Duration), or a switch between system and simulated time.

    :param min_forward: positive Duration, or None to ignore forward jumps.
    :param min_backward: negative Duration, or None to ignore backward jumps.
    :param on_clock_change: fire on a switch between system and simulated time.
    :raises ValueError: for a threshold of the wrong sign, or one that can never fire.
    """

    def __init__(self, *, min_forward: Duration | None, min_backward: Duration | None,
                 on_clock_change: bool = True) -> None:
        if min_forward is not None and min_forward.nanoseconds <= 0:
            raise ValueError('min_forward must be a positive duration (or None)')
        if min_backward is not None and min_backward.nanoseconds >= 0:
            raise ValueError('min_backward must be a negative duration (or None)')
        if min_forward is None and min_backward is None and not on_clock_change:
            raise ValueError('a jump threshold must be enabled: give min_forward, min_backward or on_clock_change')
        self.min_forward, self.min_backward, self.on_clock_change = min_forward, min_backward, on_clock_change

    def _fires(self, change: ClockChange, delta_ns: int) -> bool:
        if change in (ClockChange.ROS_TIME_ACTIVATED, ClockChange.ROS_TIME_DEACTIVATED):
            return self.on_clock_change
        return ((self.min_forward is not None and delta_ns >= self.min_forward.nanoseconds)
                or (self.min_backward is not None and delta_ns <= self.min_backward.nanoseconds))


class TimeJump:
    """What a post-jump callback is told: the ClockChange and the jump's size `delta`."""

    def __init__(self, clock_change: ClockChange, delta: Duration) -> None:
        self.clock_change, self.delta = clock_change, delta

    def __repr__(self) -> str:
        return f'TimeJump(clock_change={self.clock_change.name}, delta={self.delta})'


class JumpHandle:
    """A registered jump callback; `unregister()` (or leaving its `with` block) removes it."""

    def __init__(self, clock: 'Clock', threshold: JumpThreshold, pre_callback: Callable[[], Any] | None,
                 post_callback: Callable[[TimeJump], Any] | None) -> None:
        self._clock, self.threshold = clock, threshold
        self.pre_callback, self.post_callback = pre_callback, post_callback

    def unregister(self) -> None:
        """Stop calling this handle's callbacks."""
        with self._clock._changed:
            if self in self._clock._jump_handles:
                self._clock._jump_handles.remove(self)

    def __enter__(self) -> 'JumpHandle':
        return self

    def __exit__(self, *exc: Any) -> None:
        self.unregister()

# How often a sleep re-checks that its context is still up.
_SLEEP_SLICE_S = 0.1


class Clock:
    """A source of time that timers, rates and sleeps run on.

    :param clock_type: SYSTEM_TIME (wall clock), STEADY_TIME (monotonic) or ROS_TIME (use
        ROSClock for that, which can follow /clock).
    """
    def __new__(cls, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> 'Clock':
        # As rclpy: Clock(clock_type=ROS_TIME) is a ROSClock.
        if cls is Clock and clock_type == ClockType.ROS_TIME and isinstance(clock_type, ClockType):
            return super().__new__(ROSClock)
        return super().__new__(cls)

    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        if not isinstance(clock_type, ClockType):
            raise TypeError(f'clock_type must be a ClockType, got {clock_type!r}')
        self._clock_type = clock_type
        self._sim_time_ns: int | None = None   # simulated time, for a ROSClock whose override is on
        self._sim_epoch = 0                    # bumped when simulated time is switched on or off
        self._changed = threading.Condition()
        self._listeners: list[Callable[[], None]] = []
        self._jump_handles: list[JumpHandle] = []

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

    def create_jump_callback(self, threshold: JumpThreshold, *, pre_callback: Callable[[], Any] | None = None,
                             post_callback: Callable[[TimeJump], Any] | None = None) -> JumpHandle:
        """Call `pre_callback()` before and `post_callback(TimeJump)` after each jump of this
        clock's time that `threshold` selects (only a ROSClock's time jumps: simulated time
        switched on or off, or moved by more than the threshold).

        :return: the JumpHandle; `unregister()` it (or use it in a `with` block) to stop.
        """
        handle = JumpHandle(self, threshold, pre_callback, post_callback)
        with self._changed:
            self._jump_handles.append(handle)
        return handle

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
    def __init__(self, *, clock_type: ClockType = ClockType.ROS_TIME) -> None:
        super().__init__(clock_type=ClockType.ROS_TIME)
        self._override_ns = 0   # the simulated time, read while ROS time is active

    @property
    def ros_time_is_active(self) -> bool:
        """Whether the clock reads simulated time (from /clock) rather than system time."""
        return self._sim_time_ns is not None

    def _set_ros_time_is_active(self, enabled: bool) -> None:
        """Read simulated time (the last override) from now on, or system time again."""
        self._apply(bool(enabled), self._override_ns)

    def set_ros_time_override(self, time: Time) -> None:
        """Set the simulated time (read while ROS time is active)."""
        self._apply(self.ros_time_is_active, time.nanoseconds)

    def _set_ros_time_override(self, nanoseconds: int | None) -> None:
        """Simulated time is now `nanoseconds` (None: back to system time). Called by
        zros.time_source on Zenoh's thread."""
        if nanoseconds is None:
            self._apply(False, self._override_ns)
        else:
            self._apply(True, nanoseconds)

    def _apply(self, active: bool, override_ns: int) -> None:
        """Switch to state (active, override), running the jump callbacks it triggers (pre
        before, post after) and waking sleepers and timers."""
        with self._changed:
            was_active = self._sim_time_ns is not None
            before = self.now().nanoseconds
            after = override_ns if active else _time.time_ns()
            change: ClockChange | None = None
            if active != was_active:
                change = ClockChange.ROS_TIME_ACTIVATED if active else ClockChange.ROS_TIME_DEACTIVATED
            elif active and override_ns != self._override_ns:
                change = ClockChange.ROS_TIME_NO_CHANGE
            delta = after - before
            fired = [] if change is None else [h for h in self._jump_handles if h.threshold._fires(change, delta)]
        for handle in fired:
            if handle.pre_callback is not None:
                handle.pre_callback()
        with self._changed:
            if active != was_active:
                self._sim_epoch += 1
            self._override_ns = override_ns
            self._sim_time_ns = override_ns if active else None
            self._changed.notify_all()
            listeners = list(self._listeners)
        for listener in listeners:
            listener()
        for handle in fired:
            if handle.post_callback is not None and change is not None:
                handle.post_callback(TimeJump(change, Duration(nanoseconds=delta)))
