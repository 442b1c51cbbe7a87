"""topic_tools' decisions (nodes/topic_tools/_filters.py) and command lines, without a node."""
from __future__ import annotations

import pytest

from nodes.topic_tools import drop, relay, throttle
from nodes.topic_tools._filters import ByteThrottle, Dropper, RateThrottle


def test_rate_throttle_passes_one_message_per_full_period():
    gate = RateThrottle(2.0)
    arrivals = [i * 0.1 for i in range(21)]                  # 10 Hz for 2 s
    passed = [t for t in arrivals if gate.accept(t)]
    assert passed == pytest.approx([0.0, 0.5, 1.0, 1.5, 2.0])


def test_rate_throttle_restarts_when_time_jumps_back():
    gate = RateThrottle(1.0)
    assert gate.accept(100.0) and not gate.accept(100.5)
    assert not gate.accept(3.0)       # the clock was reset: this becomes the new start...
    assert gate.accept(4.0)           # ...and a period later the next one passes


def test_byte_throttle_keeps_each_window_near_its_budget():
    gate = ByteThrottle(bytes_per_sec=1000, window=1.0)
    passed = [t for t in (i * 0.01 for i in range(300)) if gate.accept(t, 300)]   # 30 kB/s offered
    per_second = [sum(1 for t in passed if s <= t < s + 1) for s in range(3)]
    assert per_second == [4, 4, 4]    # the message that crosses 1000 bytes still passes: 4 x 300


def test_dropper_drops_x_of_every_y():
    gate = Dropper(2, 3)
    assert [gate.accept() for _ in range(9)] == [False, False, True] * 3
    assert all(Dropper(0, 1).accept() for _ in range(5))      # relay: drop none


@pytest.mark.parametrize('make, args', [(RateThrottle, (0,)), (ByteThrottle, (0, 1.0)), (ByteThrottle, (10, 0)),
                                        (Dropper, (3, 2)), (Dropper, (0, 0)), (Dropper, (-1, 2))])
def test_filters_refuse_impossible_settings(make, args):
    with pytest.raises(ValueError):
        make(*args)


@pytest.mark.parametrize('module, argv, message', [
    (throttle, ['messages'], 'unexpected arguments'),
    (throttle, ['messages', '/scan', 'fast'], 'RATE must be a number'),
    (throttle, ['bytes', '/scan', '1000'], 'unexpected arguments'),
    (throttle, ['seconds', '/scan', '1'], 'unexpected arguments'),
    (drop, ['/scan', '1'], 'drop takes IN X Y'),
    (drop, ['/scan', 'one', '2'], 'X and Y must be integers'),
    (relay, ['/a', '/b', '/c'], 'too many arguments'),
])
def test_command_lines_in_ros_shape_refuse_what_they_cannot_parse(module, argv, message):
    """The shapes are ROS 2 topic_tools': a bad one is refused before any node exists."""
    with pytest.raises(ValueError, match=message):
        module.make(argv)
