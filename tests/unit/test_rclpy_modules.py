"""rclpy's module-level API as its own tests use it: name validators, clocks and time jumps,
parameter values from text, QoS errors (pure: no session)."""
from __future__ import annotations

import pytest

from zros.clock import Clock, ClockChange, JumpThreshold, ROSClock
from zros.clock_type import ClockType
from zros.duration import Duration
from zros.exceptions import (InvalidNamespaceException, InvalidNodeNameException, InvalidServiceNameException,
                             InvalidTopicNameException)
from zros.expand_topic_name import expand_topic_name
from zros.parameter import get_parameter_value
from zros.qos import HistoryPolicy, InvalidQoSProfileException, QoSProfile
from zros.time import Time
from zros.topic_or_service_is_hidden import topic_or_service_is_hidden
from zros.utilities import timeout_sec_to_nsec
from zros.validate_full_topic_name import validate_full_topic_name
from zros.validate_namespace import validate_namespace
from zros.validate_node_name import validate_node_name
from zros.validate_topic_name import validate_topic_name


@pytest.mark.parametrize('call, error, reason', [
    (lambda: validate_node_name('robot.arm'), InvalidNodeNameException, 'must not contain characters'),
    (lambda: validate_node_name(''), InvalidNodeNameException, 'must not be empty'),
    (lambda: validate_namespace('robot'), InvalidNamespaceException, 'must be absolute'),
    (lambda: validate_topic_name('a/9b'), InvalidTopicNameException, 'must not start with a number'),
    (lambda: validate_full_topic_name('scan', is_service=True), InvalidServiceNameException, 'must be absolute'),
    (lambda: expand_topic_name('t', 'node', ''), InvalidNamespaceException, 'namespace'),
])
def test_name_validators_raise_rclpy_s_class_with_rcl_s_reason(call, error, reason):
    with pytest.raises(error, match=reason):
        call()


def test_names_that_pass_and_hidden_names():
    assert validate_topic_name('~/{node}/scan') and validate_full_topic_name('/a/b')
    assert expand_topic_name('~/status', 'arm', '/robot') == '/robot/arm/status'
    assert topic_or_service_is_hidden('/a/_b/c') and not topic_or_service_is_hidden('/a_/b_')
    assert timeout_sec_to_nsec(None) == -1 and timeout_sec_to_nsec(0.25) == 250_000_000


def test_jump_callbacks_fire_on_threshold_and_on_clock_change():
    clock = Clock(clock_type=ClockType.ROS_TIME)
    assert isinstance(clock, ROSClock)
    seen: list = []
    threshold = JumpThreshold(min_forward=Duration(seconds=1), min_backward=None, on_clock_change=True)
    with clock.create_jump_callback(threshold, pre_callback=lambda: seen.append('pre'),
                                    post_callback=lambda jump: seen.append(jump)) as handle:
        clock.set_ros_time_override(Time(seconds=10, clock_type=ClockType.ROS_TIME))
        assert seen == []                                   # not active yet: nobody's time moved
        clock._set_ros_time_is_active(True)
        assert seen[0] == 'pre' and seen[1].clock_change == ClockChange.ROS_TIME_ACTIVATED
        seen.clear()
        clock.set_ros_time_override(Time(seconds=10.5, clock_type=ClockType.ROS_TIME))
        assert seen == []                                   # under the threshold
        clock.set_ros_time_override(Time(seconds=12, clock_type=ClockType.ROS_TIME))
        assert seen[1].clock_change == ClockChange.ROS_TIME_NO_CHANGE and seen[1].delta.nanoseconds == 1_500_000_000
        assert clock.now().nanoseconds == 12_000_000_000
    seen.clear()
    assert handle not in clock._jump_handles
    clock._set_ros_time_is_active(False)
    assert seen == [] and not clock.ros_time_is_active


def test_bad_thresholds_and_clock_types_are_refused():
    with pytest.raises(ValueError, match='min_forward'):
        JumpThreshold(min_forward=Duration(), min_backward=None)
    with pytest.raises(ValueError, match='must be enabled'):
        JumpThreshold(min_forward=None, min_backward=None, on_clock_change=False)
    with pytest.raises(TypeError):
        Clock(clock_type='STEADY_TIME')


def test_parameter_values_from_text_and_qos_errors():
    assert get_parameter_value('3.5').double_value == 3.5
    assert list(get_parameter_value('[true, false]').bool_array_value) == [True, False]
    assert get_parameter_value(' ').string_value == ' '
    assert get_parameter_value('[1, a]').string_value == '[1, a]'
    with pytest.raises(InvalidQoSProfileException):
        QoSProfile(history=HistoryPolicy.KEEP_LAST)
