"""ParameterEventHandler: callbacks per parameter and per event, fed by /parameter_events."""
from __future__ import annotations

import time

import pytest

from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.parameter import Parameter
from zros.parameter_event_handler import ParameterEventHandler


def test_a_set_parameter_reaches_its_callback_and_every_event_callback(context):
    watcher = Node('watcher', namespace='/robot', context=context)
    target = Node('arm', namespace='/robot', context=context)
    target.declare_parameter('speed', 1.0)
    handler = ParameterEventHandler(watcher)
    speeds, events, order = [], [], []
    handle = handler.add_parameter_callback('speed', 'arm', speeds.append)   # relative: /robot/arm
    handler.add_parameter_callback('speed', '/robot/arm', lambda p: order.append('newest'))
    handler.add_parameter_event_callback(events.append)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(watcher)
    executor.add_node(target)
    time.sleep(0.3)   # the subscription is matched before the change is published
    target.set_parameters([Parameter('speed', value=2.5)])
    deadline = time.monotonic() + 10
    while not speeds and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert speeds == [Parameter('speed', Parameter.Type.DOUBLE, 2.5)]
    assert order == ['newest'] and any(e.node == '/robot/arm' for e in events)
    handler.remove_parameter_callback(handle)
    with pytest.raises(RuntimeError):
        handler.remove_parameter_callback(handle)
    handler.destroy()
    executor.shutdown()
    watcher.destroy_node()
    target.destroy_node()


def test_parameters_are_read_from_an_event_built_from_parameter_objects(context):
    from interfaces.rcl_interfaces.msg import ParameterEvent
    first, second = Parameter('first', value=1), Parameter('second', value='two')
    event = ParameterEvent(node='/n', new_parameters=[first], changed_parameters=[second])
    assert ParameterEventHandler.get_parameter_from_event(event, 'second', '/n') == second
    assert ParameterEventHandler.get_parameter_from_event(event, 'second', '/other') is None
    assert set(ParameterEventHandler.get_parameters_from_event(event)) == {first, second}
