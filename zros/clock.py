"""Clocks, as rclpy.clock.Clock. ROS time follows the system clock (simulated time via
`use_sim_time` and /clock arrives with parameters)."""
from __future__ import annotations

import time as _time

from zros.duration import Duration
from zros.time import ClockType, Time

__all__ = ['Clock', 'ROSClock', 'ClockType']


class Clock:
    def __init__(self, *, clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        self._clock_type = ClockType(clock_type)
        self._sim_time_ns: int | None = None

    @property
    def clock_type(self) -> ClockType:
        return self._clock_type

    def now(self) -> Time:
        if self._clock_type == ClockType.STEADY_TIME:
            ns = _time.monotonic_ns()
        elif self._sim_time_ns is not None:
            ns = self._sim_time_ns
        else:
            ns = _time.time_ns()
        return Time(nanoseconds=ns, clock_type=self._clock_type)

    def sleep_for(self, duration: Duration) -> bool:
        _time.sleep(max(0.0, duration.nanoseconds / 1e9))
        return True

    def sleep_until(self, until: Time) -> bool:
        delay = until.nanoseconds - self.now().nanoseconds
        if delay > 0:
            _time.sleep(delay / 1e9)
        return True

    def __repr__(self) -> str:
        return f'Clock(clock_type={self._clock_type.name})'


class ROSClock(Clock):
    def __init__(self) -> None:
        super().__init__(clock_type=ClockType.ROS_TIME)

    @property
    def ros_time_is_active(self) -> bool:
        return self._sim_time_ns is not None

    def _set_ros_time_override(self, nanoseconds: int | None) -> None:
        self._sim_time_ns = nanoseconds
