"""Which messages pass: topic_tools' three decisions as plain objects (no node, no clock of their own).

Kept apart from the nodes so that the arithmetic (periods, byte windows, X of every Y) is tested
without processes, and so a program can reuse it on messages it already has.
"""
from __future__ import annotations

import collections

__all__ = ['RateThrottle', 'ByteThrottle', 'Dropper']


class RateThrottle:
    """At most one message per `1 / msgs_per_sec` seconds: a message passes when a full period
    has gone by since the last one that passed (so a 10 Hz stream throttled to 3 Hz gives one
    every 0.4 s, as ROS's throttle does, not 3 Hz on average)."""

    def __init__(self, msgs_per_sec: float) -> None:
        if not msgs_per_sec > 0:
            raise ValueError(f'msgs_per_sec must be > 0, got {msgs_per_sec!r}')
        self.period = 1.0 / msgs_per_sec
        self._last: float | None = None

    def accept(self, now: float, nbytes: int = 0) -> bool:
        """Whether a message arriving at `now` [s] passes."""
        if self._last is not None and now < self._last:
            self._last = now             # time jumped back (a simulation reset): start again from here
        if self._last is None or now - self._last >= self.period:
            self._last = now
            return True
        return False


class ByteThrottle:
    """A message passes while the bytes passed in the last `window` seconds are under
    `bytes_per_sec` (ROS's `throttle bytes`: the budget is per window, the message that crosses
    it still passes)."""

    def __init__(self, bytes_per_sec: int, window: float) -> None:
        if bytes_per_sec <= 0 or not window > 0:
            raise ValueError(f'bytes_per_sec and window must be > 0, got {bytes_per_sec!r} and {window!r}')
        self.bytes_per_sec, self.window = bytes_per_sec, window
        self._sent: collections.deque[tuple[float, int]] = collections.deque()
        self._total = 0

    def accept(self, now: float, nbytes: int) -> bool:
        while self._sent and self._sent[0][0] < now - self.window:
            self._total -= self._sent.popleft()[1]
        if self._total >= self.bytes_per_sec:
            return False
        self._sent.append((now, nbytes))
        self._total += nbytes
        return True


class Dropper:
    """Drops the first `x` of every `y` messages and passes the rest."""

    def __init__(self, x: int, y: int) -> None:
        if not 0 <= x <= y or y < 1:
            raise ValueError(f'drop needs 0 <= X <= Y and Y >= 1, got X={x!r} Y={y!r}')
        self.x, self.y = x, y
        self._count = 0

    def accept(self, now: float = 0.0, nbytes: int = 0) -> bool:
        passes = self._count >= self.x
        self._count = (self._count + 1) % self.y
        return passes
