"""A Rate is also a timer the executor services (rclpy's model), while it still sleeps on
its own in a script that never spins."""
from __future__ import annotations

import threading
import time

import pytest

from zros.executors import SingleThreadedExecutor
from zros.node import Node


def test_spin_once_returns_while_another_thread_sleeps_on_a_rate(context):
    node = Node('paced', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    rate = node.create_rate(20.0)
    ticks = []
    sleeper = threading.Thread(target=lambda: [rate.sleep() or ticks.append(1) for _ in range(4)], daemon=True)
    sleeper.start()
    start = time.monotonic()
    while sleeper.is_alive() and time.monotonic() - start < 5.0:
        executor.spin_once()   # no timeout: returns because the rate's timer fires
    assert len(ticks) == 4
    assert len(node.timers) == 1 and node.destroy_rate(rate) and len(node.timers) == 0
    executor.shutdown()
    node.destroy_node()


def test_a_rate_paces_a_loop_without_spinning(context):
    node = Node('unspun', context=context)
    rate = node.create_rate(50.0)
    start = time.monotonic()
    for _ in range(5):
        rate.sleep()
    assert 0.06 <= time.monotonic() - start < 1.0
    node.destroy_node()


def test_a_rate_needs_a_positive_number(context):
    node = Node('unpaced', context=context)
    with pytest.raises(TypeError):
        node.create_rate(None)
    with pytest.raises(ValueError):
        node.create_rate(0.0)
    assert not list(node.timers)
    node.destroy_node()


def test_destroying_a_rate_itself_takes_its_timer_off_the_node(context):
    # A navigation server makes a rate per goal loop and destroys it with rate.destroy(); each
    # forgotten timer would wake the executor for the rest of the node's life (the soak's leak).
    node = Node('looping', context=context)
    for _ in range(50):
        rate = node.create_rate(20.0)
        rate.sleep()
        rate.destroy()
        rate.destroy()   # twice is harmless
    assert not list(node.timers)
    with pytest.raises(RuntimeError):
        rate.sleep()
    assert node.destroy_rate(rate) and not list(node.timers)
    node.destroy_node()
