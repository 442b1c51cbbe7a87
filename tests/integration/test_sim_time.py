"""Simulated time (issue 12, item 6): with use_sim_time, timers, rates and sleeps run on /clock.

A program (run as a process) has a 0.5 s timer spinning in a thread, and a 2 Hz Rate loop and
a 1 s `sleep_for` in its main thread. The test publishes /clock itself: at 10x real time,
then not at all (simulated time stands still), then again.
"""
from __future__ import annotations

import re
import sys
import time

import pytest

from zros.node import Node

from interfaces.rosgraph_msgs.msg import Clock

PROGRAM = '''
import sys, threading
import zros
from zros.duration import Duration
from zros.executors import ExternalShutdownException
from zros.exceptions import ROSInterruptException
from zros.node import Node

def say(text):   # one write per line: the timer thread and the main thread both print
    sys.stdout.write(text + '\\n')
    sys.stdout.flush()

zros.init(args=sys.argv)
node = Node('sim_timed')
clock = node.get_clock()
node.create_timer(0.5, lambda: say(f'tick {clock.now().nanoseconds}'))
def spin():
    try:
        zros.spin(node)
    except ExternalShutdownException:
        pass
threading.Thread(target=spin, daemon=True).start()
say(f'ready sim={clock.ros_time_is_active}')
try:
    rate = node.create_rate(2.0)
    for _ in range(3):
        rate.sleep()
        say(f'rate {clock.now().nanoseconds}')
    start = clock.now().nanoseconds
    clock.sleep_for(Duration(seconds=2.0))
    say(f'slept {start} {clock.now().nanoseconds}')
    while zros.ok():
        rate.sleep()
except (KeyboardInterrupt, ROSInterruptException):
    pass
'''

SEC = 1_000_000_000


def _times(output: str, label: str) -> list[int]:
    return [int(v) for v in re.findall(rf'^{label} (\d+)', output, re.M)]


def _drive(publisher, start_s: float, end_s: float, speed: float = 2.0, step_s: float = 0.02) -> None:
    """Publish /clock from start_s to end_s of simulated time at `speed` x real time. The checks
    allow a call a quarter of a simulated second after it fell due: at 2x that is 125 ms of real
    time for the program to get a CPU (at 10x, 25 ms were too few on a loaded 2-core machine)."""
    t = start_s
    while t <= end_s + 1e-9:
        sec = int(t)
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = sec, int(round((t - sec) * SEC))
        publisher.publish(msg)
        time.sleep(step_s / speed)
        t += step_s


@pytest.fixture
def sim_program(context, spawn, wait_for):
    node = Node('sim_clock_driver', context=context)
    publisher = node.create_publisher(Clock, '/clock', 10)
    child = spawn(sys.executable, '-c', PROGRAM, '--ros-args', '-p', 'use_sim_time:=true', name='sim_timed')
    child.wait_for_output('ready sim=True', timeout=15)
    wait_for(lambda: node.count_subscribers('/clock') >= 1, timeout=10, message='the /clock subscription')
    time.sleep(0.3)   # the program's publisher-subscriber link
    return child, publisher


def test_timers_rates_and_sleeps_follow_the_clock(sim_program, wait_for):
    child, publisher = sim_program
    # Simulated time reads 0 until the first /clock: nothing has fired in real time.
    time.sleep(1.2)
    assert _times(child.output(), 'tick') == [] and _times(child.output(), 'rate') == []

    _drive(publisher, 10.0, 12.0)                      # 2 s of simulated time in ~1 s
    # Due at 10.0 (the first /clock), 10.5, 11.0, 11.5 and 12.0 of simulated time; each call
    # reads the clock when it runs, a few /clock steps after it fell due at most.
    wait_for(lambda: len(_times(child.output(), 'tick')) == 5, timeout=5, message=child.output)
    ticks = _times(child.output(), 'tick')
    assert all(due <= tick < due + SEC // 4 for due, tick in zip(range(10 * SEC, 13 * SEC, SEC // 2), ticks))
    rates = _times(child.output(), 'rate')
    assert len(rates) == 3, child.output()
    assert all(due <= rate < due + SEC // 4 for due, rate in zip(range(10 * SEC, 12 * SEC, SEC // 2), rates))

    # Simulated time stands still: no timer call, and the sleep does not end.
    before = child.output()
    time.sleep(1.5)
    assert child.output() == before
    assert 'slept' not in before

    _drive(publisher, 12.0, 13.5)                      # time moves on: everything resumes
    wait_for(lambda: 'slept' in child.output() and len(_times(child.output(), 'tick')) == 8, timeout=5,
             message=child.output)
    ticks = _times(child.output(), 'tick')
    assert all(due <= tick < due + SEC // 4 for due, tick in zip(range(12 * SEC + SEC // 2, 14 * SEC, SEC // 2),
                                                                    ticks[5:]))
    start, end = map(int, re.search(r'^slept (\d+) (\d+)', child.output(), re.M).groups())
    assert end - start >= 2 * SEC and end <= 13_500_000_000


def test_sim_time_going_backwards_restarts_the_timer(sim_program, wait_for):
    child, publisher = sim_program
    _drive(publisher, 50.0, 51.0)
    wait_for(lambda: len(_times(child.output(), 'tick')) == 3, timeout=5, message=child.output)   # 50, 50.5, 51
    _drive(publisher, 5.0, 6.0)                        # a restarted simulation
    # The schedule starts again from 5.0 s: calls at 5.5 and 6.0, not at 51.5 s.
    wait_for(lambda: len(_times(child.output(), 'tick')) == 5, timeout=5, message=child.output)
    time.sleep(0.3)
    ticks = _times(child.output(), 'tick')
    assert len(ticks) == 5 and 5 * SEC + SEC // 2 <= ticks[3] < ticks[4] < 6 * SEC + SEC // 4, ticks
