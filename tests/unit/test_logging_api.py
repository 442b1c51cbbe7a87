"""rclpy.logging's module API and call-site filters, as rclpy's tests define them (pure)."""
from __future__ import annotations

from pathlib import Path

import pytest

from zros import logging as zlog
from zros.clock import ROSClock
from zros.logging import LoggingSeverity
from zros.time import Time


@pytest.fixture(autouse=True)
def _fresh_levels():
    zlog.clear_config()
    yield
    zlog.clear_config()


def test_levels_inherit_from_parent_then_root():
    zlog.set_logger_level('arm', LoggingSeverity.ERROR)
    assert zlog.get_logger_effective_level('arm.gripper') == LoggingSeverity.ERROR
    zlog.clear_config()
    assert zlog.get_logger_effective_level('arm.gripper') == zlog._root_logger.get_effective_level()
    zlog._root_logger.set_level(LoggingSeverity.UNSET)   # the root keeps even UNSET
    assert zlog._root_logger.get_effective_level() == LoggingSeverity.UNSET


def test_names_and_severities_from_text():
    with pytest.raises(ValueError, match='Logger name must not be empty'):
        zlog.get_logger('')
    with pytest.raises(ValueError, match='Child logger name must not be empty'):
        zlog.get_logger('arm').get_child('')
    assert zlog.get_logging_severity_from_string('WARN') == LoggingSeverity.WARN
    with pytest.raises(RuntimeError):
        zlog.get_logging_severity_from_string('loud')


def test_logging_directory_follows_ros_variables(monkeypatch):
    monkeypatch.delenv('ROS_LOG_DIR', raising=False)
    monkeypatch.delenv('ROS_HOME', raising=False)
    monkeypatch.setenv('HOME', '/home/robot')
    assert zlog.get_logging_directory() == Path('/home/robot/.ros/log')
    monkeypatch.setenv('ROS_HOME', '/data/ros')
    assert zlog.get_logging_directory() == Path('/data/ros/log')
    monkeypatch.setenv('ROS_LOG_DIR', '/var/log/ros')
    assert zlog.get_logging_directory() == Path('/var/log/ros')


def test_filters_run_throttle_then_skip_first_then_once():
    logger = zlog.get_logger('filtered')
    assert [logger.info('m', skip_first=True, once=True) for _ in range(4)] == [False, True, False, False]
    clock = ROSClock()
    clock._set_ros_time_is_active(True)
    results = []
    for second in range(5):
        clock.set_ros_time_override(Time(seconds=second, clock_type=clock.clock_type))
        results.append(logger.info('t', throttle_duration_sec=2, throttle_time_source_type=clock))
    assert results == [False, False, True, False, True]   # on a clock, the first waits too


def test_a_call_site_keeps_its_options_and_severity():
    logger = zlog.get_logger('strict')
    with pytest.raises(TypeError, match='not one of the recognized'):
        logger.info('m', bogus=True)
    with pytest.raises(TypeError, match='required parameter'):
        logger.info('m', throttle_time_source_type=ROSClock())
    with pytest.raises(ValueError, match='severity cannot be changed'):
        for severity in (LoggingSeverity.INFO, LoggingSeverity.WARN):
            logger.log('m', severity, once=True)
    for severity in (LoggingSeverity.INFO, LoggingSeverity.WARN):   # a plain call site keeps no state
        assert logger.log('m', severity)
    with pytest.raises(ValueError, match='parameters cannot be changed'):
        for duration in (1, 2):
            logger.info('m', throttle_duration_sec=duration)
