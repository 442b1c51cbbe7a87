"""Time and Duration keep rcl's signed 64-bit range and rclpy's typing rules (pure)."""
from __future__ import annotations

import pytest

from zros.clock_type import ClockType
from zros.duration import Duration, Infinite
from zros.time import Time


def test_values_outside_64_bits_overflow():
    assert Time(nanoseconds=2**63 - 1).nanoseconds == 2**63 - 1
    with pytest.raises(OverflowError):
        Time(nanoseconds=2**63)
    assert Duration(nanoseconds=-2**63).nanoseconds == -2**63
    for nanoseconds in (2**63, -2**63 - 1):
        with pytest.raises(OverflowError):
            Duration(nanoseconds=nanoseconds)
    with pytest.raises(OverflowError):
        Duration(nanoseconds=1) + Time(nanoseconds=2**63 - 1)


def test_a_clock_type_must_be_a_clock_type():
    with pytest.raises(TypeError):
        Time(clock_type='SYSTEM_TIME')


def test_duration_plus_time_is_a_time_and_the_rest_is_a_type_error():
    time = Time(nanoseconds=1, clock_type=ClockType.STEADY_TIME)
    later = Duration(nanoseconds=1) + time
    assert isinstance(later, Time) and later.nanoseconds == 2 and later.clock_type == ClockType.STEADY_TIME
    with pytest.raises(TypeError):
        Duration(nanoseconds=1) - time
    with pytest.raises(TypeError):
        time + time


def test_times_of_two_clocks_are_not_even_equal_or_unequal():
    system, steady = Time(clock_type=ClockType.SYSTEM_TIME), Time(clock_type=ClockType.STEADY_TIME)
    with pytest.raises(TypeError):
        system == steady  # noqa: B015 - the comparison itself raises
    assert Time() != Duration() and not Time() == 0


def test_infinite_prints_as_such():
    assert str(Infinite) == 'Infinite' and str(Duration(nanoseconds=3)) == '3 nanoseconds'
