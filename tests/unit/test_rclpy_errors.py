"""The exceptions zros raises where rclpy raises the C layer's (`_rclpy.RCLError` and kin), and
the shutdown precondition: code written against rclpy catches what zros raises."""
from __future__ import annotations

import pytest

from zros.arguments import RosArgsError, UnknownRosArgsError, parse_ros_args
from zros.config import settings_from_env
from zros.context import Context
from zros.errors import RCLError
from zros.impl.implementation_singleton import rclpy_implementation
from zros.lifecycle.state_machine import LifecycleStateMachine, TransitionError


def test_unknown_ros_args_are_all_listed_in_one_error():
    with pytest.raises(UnknownRosArgsError) as info:
        parse_ros_args(['prog', '--ros-args', 'typo', '-r', 'a:=b', '--other'])
    assert "['typo', '--other']" in str(info.value)


def test_ros_args_errors_read_as_rcl_writes_them():
    with pytest.raises(RosArgsError, match=r"^Failed to parse ROS arguments: .*'not-a-remap'"):
        parse_ros_args(['--ros-args', '-r', 'not-a-remap'])


def test_ros_args_errors_are_runtime_errors_as_in_rclpy():
    assert issubclass(RosArgsError, RCLError) and issubclass(RCLError, RuntimeError)
    assert issubclass(RosArgsError, ValueError)   # what zros code caught before


def test_the_shim_names_zros_own_classes():
    assert rclpy_implementation.RCLError is RCLError
    assert rclpy_implementation.UnknownROSArgsError is UnknownRosArgsError
    assert rclpy_implementation.RCLInvalidROSArgsError is RosArgsError


def test_a_refused_lifecycle_transition_is_an_rcl_error():
    machine = LifecycleStateMachine()
    assert machine.current_state == (1, 'unconfigured')
    with pytest.raises(RCLError):
        machine.begin('activate')
    assert issubclass(TransitionError, rclpy_implementation.RCLError)


def test_an_out_of_range_domain_id_is_a_runtime_error():
    with pytest.raises(RuntimeError, match='0-232'):
        settings_from_env({}, domain_id=-1)


def test_init_refuses_arguments_that_are_not_utf8_before_opening_anything():
    context = Context()
    with pytest.raises(UnicodeEncodeError):
        context.init(['node.py', 'Ragnar\udcc3\udcb6k'])
    assert not context.ok()


def test_shutting_down_a_context_that_is_not_up_raises_unless_a_signal_did_it():
    context = Context()
    with pytest.raises(RuntimeError, match='try_shutdown'):
        context.check_can_shut_down()
    context._stop_requested = True      # what a SIGINT's watcher sets before it shuts down
    context.check_can_shut_down()
