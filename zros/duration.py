"""Durations, as rclpy.duration.Duration."""
from __future__ import annotations

from functools import total_ordering

__all__ = ['Duration', 'Infinite']

# rcl holds times and durations as signed 64-bit nanoseconds.
INT64_MIN, INT64_MAX = -2**63, 2**63 - 1


@total_ordering
class Duration:
    """A signed span of time in nanoseconds, held in rcl's signed 64 bits.

    :param seconds: Seconds (may be fractional).
    :param nanoseconds: Nanoseconds added to `seconds`.
    :raises OverflowError: If the total does not fit a signed 64-bit count of nanoseconds.
    """

    __slots__ = ('_nanoseconds',)

    def __init__(self, *, seconds: float = 0, nanoseconds: int = 0) -> None:
        total = int(seconds * 1_000_000_000) + int(nanoseconds)
        if not INT64_MIN <= total <= INT64_MAX:
            raise OverflowError(f'a Duration of {total} ns does not fit in 64 bits')
        self._nanoseconds = total

    @property
    def nanoseconds(self) -> int:
        """The duration in nanoseconds (negative for a span backwards)."""
        return self._nanoseconds

    def to_msg(self):
        """The duration as a message.

        :return: A builtin_interfaces/msg/Duration.
        """
        from interfaces.builtin_interfaces.msg import Duration as DurationMsg
        sec, nsec = divmod(self._nanoseconds, 1_000_000_000)
        return DurationMsg(sec=sec, nanosec=nsec)

    @classmethod
    def from_msg(cls, msg) -> 'Duration':
        """Build a Duration from a message.

        :param msg: A builtin_interfaces/msg/Duration.
        :return: The duration.
        """
        return cls(seconds=msg.sec, nanoseconds=msg.nanosec)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Duration) and self._nanoseconds == other._nanoseconds

    def __lt__(self, other: 'Duration') -> bool:
        if not isinstance(other, Duration):
            return NotImplemented
        return self._nanoseconds < other._nanoseconds

    def __hash__(self) -> int:
        return hash(self._nanoseconds)

    def __add__(self, other: 'Duration') -> 'Duration':
        if not isinstance(other, Duration):
            return NotImplemented   # Duration + Time is Time's __radd__
        return Duration(nanoseconds=self._nanoseconds + other._nanoseconds)

    def __sub__(self, other: 'Duration') -> 'Duration':
        if not isinstance(other, Duration):
            return NotImplemented   # a Duration minus a Time is meaningless: TypeError
        return Duration(nanoseconds=self._nanoseconds - other._nanoseconds)

    def __mul__(self, factor: float) -> 'Duration':
        return Duration(nanoseconds=int(self._nanoseconds * factor))

    def __repr__(self) -> str:
        return f'Duration(nanoseconds={self._nanoseconds})'

    def __str__(self) -> str:
        return 'Infinite' if self._nanoseconds == INT64_MAX else f'{self._nanoseconds} nanoseconds'


#: The longest Duration, which rclpy uses for "wait for ever".
Infinite = Duration(nanoseconds=INT64_MAX)
