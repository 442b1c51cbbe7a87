"""nav2_simple_commander.line_iterator.LineIterator: steps, clamping and bad input (pure)."""
from __future__ import annotations

import pytest

from zros.nav2_simple_commander.line_iterator import LineIterator


def _walk(iterator: LineIterator) -> list[tuple[float, float]]:
    points = []
    while iterator.isValid() and len(points) < 100:
        points.append((iterator.getX(), iterator.getY()))
        iterator.advance()
    return points


def test_steps_follow_the_slope_and_end_on_the_end_point():
    assert _walk(LineIterator(0, 0, 2, -4, 1)) == [(0, 0), (1, -2), (2, -4)]
    assert _walk(LineIterator(3, 1, 3, -1, 1)) == [(3, 1), (3, 0), (3, -1)]       # vertical: along y
    assert _walk(LineIterator(0, 0, 2.5, 0, 1)) == [(0, 0), (1, 0), (2, 0), (2.5, 0)]  # last step clamped
    assert _walk(LineIterator(0, 0, 1, 1, 10)) == [(0, 0), (1, 1)]


def test_length_and_ends():
    line = LineIterator(1, 2, 4, 6)
    assert line.get_line_length() == 5.0
    assert (line.getX0(), line.getY0(), line.getX1(), line.getY1()) == (1, 2, 4, 6)


@pytest.mark.parametrize('args, error', [
    ((0, 0, '1', 1, 1), TypeError), ((0, 0, 1, 1, True), TypeError),
    ((0, 0, 1, 1, 0), ValueError), ((0, 0, 1, 1, -1), ValueError), ((2, 2, 2, 2, 1), ValueError),
])
def test_bad_input_is_refused(args, error):
    with pytest.raises(error):
        LineIterator(*args)
