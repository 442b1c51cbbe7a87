"""nav2_simple_commander.line_iterator: walk a straight segment in fixed steps.

Used by FootprintCollisionChecker to sample a footprint's edges. The step is taken along x
(the y increment follows the slope), or along y for a vertical segment, and the last step is
clamped so the walk ends exactly on the segment's end point.
"""
from __future__ import annotations

import math
from numbers import Real

__all__ = ['LineIterator']


class LineIterator:
    """Points from (x0, y0) to (x1, y1), `step_size` apart along the walking axis.

    :param x0: start x.
    :param y0: start y.
    :param x1: end x.
    :param y1: end y.
    :param step_size: the step along x (along y for a vertical segment); must be > 0.
    :raises TypeError: when a coordinate or the step is not a number.
    :raises ValueError: for a step <= 0 or a segment of zero length.
    """

    def __init__(self, x0: float, y0: float, x1: float, y1: float, step_size: float = 1.0) -> None:
        values = (x0, y0, x1, y1, step_size)
        if not all(isinstance(v, Real) and not isinstance(v, bool) for v in values):
            raise TypeError('LineIterator takes numbers: x0, y0, x1, y1 and step_size')
        if step_size <= 0:
            raise ValueError(f'step_size must be greater than 0, got {step_size}')
        if x0 == x1 and y0 == y1:
            raise ValueError('the line has zero length: its start and end points are the same')
        self._x0, self._y0, self._x1, self._y1 = x0, y0, x1, y1
        self._step_size = step_size
        if x1 != x0:
            slope = (y1 - y0) / (x1 - x0)
            self._dx = math.copysign(step_size, x1 - x0)
            self._dy = slope * self._dx
        else:
            self._dx = 0.0
            self._dy = math.copysign(step_size, y1 - y0)
        self._x, self._y = x0, y0
        self._valid = True

    def isValid(self) -> bool:  # noqa: N802 - Nav2's names
        """Whether the current point is still on the segment."""
        return self._valid

    def advance(self) -> None:
        """Step to the next point; past the end point the iterator becomes invalid."""
        if (self._x, self._y) == (self._x1, self._y1):
            self._valid = False
            return
        x, y = self._x + self._dx, self._y + self._dy
        overshoot = ((self._dx > 0 and x > self._x1) or (self._dx < 0 and x < self._x1)
                     or (self._dx == 0 and ((self._dy > 0 and y > self._y1) or (self._dy < 0 and y < self._y1))))
        self._x, self._y = (self._x1, self._y1) if overshoot else (x, y)

    def getX(self) -> float:  # noqa: N802
        return self._x

    def getY(self) -> float:  # noqa: N802
        return self._y

    def getX0(self) -> float:  # noqa: N802
        return self._x0

    def getY0(self) -> float:  # noqa: N802
        return self._y0

    def getX1(self) -> float:  # noqa: N802
        return self._x1

    def getY1(self) -> float:  # noqa: N802
        return self._y1

    def get_line_length(self) -> float:
        """The segment's length."""
        return math.hypot(self._x1 - self._x0, self._y1 - self._y0)
