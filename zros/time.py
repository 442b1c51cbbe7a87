"""Points in time, as rclpy.time.Time, convertible to builtin_interfaces/msg/Time."""
from __future__ import annotations

import enum
from functools import total_ordering

from zros.duration import INT64_MAX, Duration

__all__ = ['Time', 'ClockType']


class ClockType(enum.IntEnum):
    """Which clock a Time was read from; times of different clock types do not compare."""
    UNINITIALIZED = 0
    ROS_TIME = 1
    SYSTEM_TIME = 2
    STEADY_TIME = 3


@total_ordering
class Time:
    """A point in time on one clock, as rclpy.time.Time, in integer nanoseconds.

    :param seconds: Seconds since the clock's epoch (may be fractional).
    :param nanoseconds: Nanoseconds added to `seconds`.
    :param clock_type: The clock this time belongs to.
    :raises ValueError: If the total is negative.
    :raises OverflowError: If it does not fit rcl's signed 64 bits.
    :raises TypeError: If `clock_type` is not a ClockType.
    """
    __slots__ = ('_nanoseconds', '_clock_type')

    def __init__(self, *, seconds: float = 0, nanoseconds: int = 0,
                 clock_type: ClockType = ClockType.SYSTEM_TIME) -> None:
        if not isinstance(clock_type, ClockType):
            raise TypeError(f'clock_type must be a ClockType, got {clock_type!r}')
        total = int(seconds * 1_000_000_000) + int(nanoseconds)
        if total < 0:
            raise ValueError('Time must not be negative')
        if total > INT64_MAX:
            raise OverflowError(f'a Time of {total} ns does not fit in 64 bits')
        self._nanoseconds = total
        self._clock_type = clock_type

    @property
    def nanoseconds(self) -> int:
        """The time in nanoseconds since the clock's epoch."""
        return self._nanoseconds

    @property
    def clock_type(self) -> ClockType:
        """The ClockType of the clock this time belongs to."""
        return self._clock_type

    def seconds_nanoseconds(self) -> tuple[int, int]:
        """Split the time into whole seconds and the nanoseconds left over.

        :return: ``(seconds, nanoseconds)``, as builtin_interfaces/msg/Time holds it.
        """
        return divmod(self._nanoseconds, 1_000_000_000)

    def to_msg(self):
        """The time as a message, for a header's `stamp`.

        :return: A builtin_interfaces/msg/Time.
        """
        from interfaces.builtin_interfaces.msg import Time as TimeMsg
        sec, nsec = divmod(self._nanoseconds, 1_000_000_000)
        return TimeMsg(sec=sec, nanosec=nsec)

    @classmethod
    def from_msg(cls, msg, clock_type: ClockType = ClockType.ROS_TIME) -> 'Time':
        """Build a Time from a message.

        :param msg: A builtin_interfaces/msg/Time (a header's `stamp`).
        :param clock_type: The clock the stamp was taken on; ROS time, as rclpy assumes.
        :return: The time.
        """
        return cls(seconds=msg.sec, nanoseconds=msg.nanosec, clock_type=clock_type)

    def _check(self, other: 'Time') -> None:
        if not isinstance(other, Time):
            raise TypeError(f'cannot compare Time with {type(other).__name__}')
        if other._clock_type != self._clock_type:
            raise TypeError("Can't compare times with different clock types")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Time):
            return False
        self._check(other)   # as rclpy: times of two clocks are not comparable, even for equality
        return self._nanoseconds == other._nanoseconds

    def __lt__(self, other: 'Time') -> bool:
        self._check(other)
        return self._nanoseconds < other._nanoseconds

    def __hash__(self) -> int:
        return hash((self._nanoseconds, self._clock_type))

    def __add__(self, other: Duration) -> 'Time':
        if not isinstance(other, Duration):
            return NotImplemented
        return Time(nanoseconds=self._nanoseconds + other.nanoseconds, clock_type=self._clock_type)

    __radd__ = __add__

    def __sub__(self, other):
        if isinstance(other, Time):
            self._check(other)
            return Duration(nanoseconds=self._nanoseconds - other._nanoseconds)
        if isinstance(other, Duration):
            return Time(nanoseconds=self._nanoseconds - other.nanoseconds, clock_type=self._clock_type)
        return NotImplemented

    def __repr__(self) -> str:
        return f'Time(nanoseconds={self._nanoseconds}, clock_type={self._clock_type.name})'
