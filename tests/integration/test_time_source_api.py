"""rclpy's TimeSource as user code drives it: made with or without a node, ROSClocks attached
to it, following the node's `use_sim_time` and /clock, and moved from node to node."""
from __future__ import annotations

import pytest

from zros.clock import Clock, ClockType, ROSClock
from zros.node import Node
from zros.parameter import Parameter
from zros.time_source import TimeSource

from interfaces.rosgraph_msgs.msg import Clock as ClockMsg

SEC = 1_000_000_000


def _sim_time(node: Node, enabled: bool) -> None:
    node.set_parameters([Parameter('use_sim_time', Parameter.Type.BOOL, enabled)])


def test_only_ros_clocks_can_be_attached():
    source = TimeSource()
    source.attach_clock(ROSClock())
    for clock_type in (ClockType.SYSTEM_TIME, ClockType.STEADY_TIME):
        with pytest.raises(ValueError, match='ROSClock'):
            source.attach_clock(Clock(clock_type=clock_type))


def test_without_a_node_the_source_decides_whether_clocks_read_ros_time():
    source = TimeSource()
    clock = ROSClock()
    clock._set_ros_time_is_active(True)
    source.attach_clock(clock)
    assert not clock.ros_time_is_active and source._clock_sub is None
    source.ros_time_is_active = True
    assert clock.ros_time_is_active and clock.now().nanoseconds == 0
    assert source._clock_sub is None   # no node to subscribe through


def test_attached_clocks_follow_use_sim_time_and_clock_topic(context, wait_for):
    node = Node('time_source_user', context=context)
    source = TimeSource(node=node)
    clock = ROSClock()
    source.attach_clock(clock)
    assert not source.ros_time_is_active and source._clock_sub is None

    _sim_time(node, True)
    assert source.ros_time_is_active and clock.ros_time_is_active
    assert source._clock_sub is not None and clock.now().nanoseconds == 0

    publisher = node.create_publisher(ClockMsg, '/clock', 1)
    msg = ClockMsg()
    msg.clock.sec = 7
    # the node's own time source has its own /clock subscription: both see the sample
    wait_for(lambda: publisher.publish(msg) or (clock.now().nanoseconds == 7 * SEC
                                                and node.get_clock().now().nanoseconds == 7 * SEC))

    late = ROSClock()
    source.attach_clock(late)   # a clock attached later starts at the last /clock time
    assert late.ros_time_is_active and late.now().nanoseconds == 7 * SEC

    _sim_time(node, False)
    assert not clock.ros_time_is_active and source._clock_sub is None
    node.destroy_node()


def test_moving_to_another_node_drops_the_old_subscription(context):
    first = Node('time_source_first', context=context)
    second = Node('time_source_second', context=context)
    source = TimeSource(node=first)
    _sim_time(first, True)
    assert source._clock_sub is not None
    source.attach_node(second)   # second's use_sim_time is false
    assert source._get_node() is second and source._clock_sub is None
    assert not source.ros_time_is_active
    _sim_time(first, False)      # first is no longer followed
    _sim_time(first, True)
    assert not source.ros_time_is_active
    source.detach_node()
    assert source._get_node() is None
    first.destroy_node()
    second.destroy_node()
