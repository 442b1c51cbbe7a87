"""nav2_velocity_smoother: the limits as plain code (acceleration per axis, direction kept with
scale_velocities, the stop on input timeout), then the node as a process between `cmd_vel_nav`
and `cmd_vel` as Nav2's navigation_launch.py remaps it."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import activate, wait_until
from zros.navigation.velocity_smoother import VelocitySmoother, VelocitySmootherParams

FREQ = 10.0


def _smoother(**kw) -> VelocitySmoother:
    return VelocitySmoother(VelocitySmootherParams(smoothing_frequency=FREQ, **kw))


def test_acceleration_is_limited_per_axis_and_deceleration_uses_max_decel():
    s = _smoother(max_accel=[1.0, 0.0, 2.0], max_decel=[-3.0, 0.0, -4.0])
    s.command([0.5, 0.0, 1.0], now=0.0)
    first = s.step(0.0)
    assert first == pytest.approx([0.1, 0.0, 0.2])            # accel / frequency per period
    outs = [s.step(0.1 * i) for i in range(1, 10)]
    assert outs[-1] == pytest.approx([0.5, 0.0, 1.0])          # reaches the command and stays
    s.command([0.0, 0.0, -1.0], now=1.0)
    down = s.step(1.0)
    assert down == pytest.approx([0.2, 0.0, 0.6])              # slowing down (and through zero): max_decel
    assert s.limit(np.array([0.0, 0.0, 0.0]), np.array([9.0, 9.0, -9.0])) == pytest.approx([0.1, 0.0, -0.2])


def test_velocity_limits_and_deadband():
    s = _smoother(max_velocity=[0.26, 0.0, 1.0], min_velocity=[-0.26, 0.0, -1.0], max_accel=[100, 0, 100],
                  max_decel=[-100, 0, -100], deadband_velocity=[0.05, 0.0, 0.1])
    assert s.limit(np.zeros(3), np.array([1.0, 0.3, -3.0])) == pytest.approx([0.26, 0.0, -1.0])
    assert s.limit(np.zeros(3), np.array([0.04, 0.0, 0.09])) == pytest.approx([0.0, 0.0, 0.0])


def test_scale_velocities_keeps_the_commanded_direction():
    cmd = np.array([0.5, 0.0, 2.0])
    plain = _smoother(max_accel=[2.5, 0.0, 3.2]).limit(np.zeros(3), cmd)
    scaled = _smoother(max_accel=[2.5, 0.0, 3.2], scale_velocities=True).limit(np.zeros(3), cmd)
    assert plain == pytest.approx([0.25, 0.0, 0.32])           # each axis at its own limit: turns less
    assert scaled[2] == pytest.approx(0.32)                    # the most limited axis sets the factor
    assert scaled[0] / scaled[2] == pytest.approx(cmd[0] / cmd[2])


def test_timeout_brings_the_robot_to_zero_once_then_stays_silent():
    s = _smoother(velocity_timeout=0.5, max_decel=[-10.0, 0.0, -10.0])
    assert s.step(0.0) is None                                  # nothing commanded yet
    s.command([0.3, 0.0, 0.0], now=0.0)
    for i in range(5):
        s.step(0.1 * i)
    assert s.last[0] == pytest.approx(0.3)
    stop = s.step(0.7)
    assert stop == pytest.approx([0.0, 0.0, 0.0])               # within max_decel: one period to zero
    assert s.step(0.8) is None and s.step(0.9) is None
    s.command([0.1, 0.0, 0.0], now=1.0)
    assert s.step(1.0) == pytest.approx([0.1, 0.0, 0.0])        # a new command wakes it


def test_closed_loop_starts_from_the_measured_velocity_and_bad_input_is_refused():
    s = _smoother(feedback='CLOSED_LOOP')
    s.command([0.5, 0.0, 0.0], now=0.0)
    assert s.step(0.0, measured=np.array([0.2, 0.0, 0.0])) == pytest.approx([0.45, 0.0, 0.0])
    assert not s.command([float('nan'), 0.0, 0.0], now=0.1)
    with pytest.raises(ValueError, match='max_decel'):
        VelocitySmoother(VelocitySmootherParams(max_decel=[2.5, 0.0, -3.2]))
    with pytest.raises(ValueError, match='3 values'):
        VelocitySmoother(VelocitySmootherParams(max_velocity=[0.5, 1.0]))
    with pytest.raises(ValueError, match='feedback'):
        VelocitySmoother(VelocitySmootherParams(feedback='SOMETIMES'))


def test_node_smooths_cmd_vel_nav_into_cmd_vel(spawn, probe, tmp_path):
    from interfaces.geometry_msgs.msg import Twist
    params = tmp_path / 'params.yaml'
    params.write_text('velocity_smoother:\n  ros__parameters:\n    smoothing_frequency: 20.0\n'
                      '    max_velocity: [0.26, 0.0, 1.0]\n    min_velocity: [-0.26, 0.0, -1.0]\n'
                      '    max_accel: [1.0, 0.0, 3.2]\n    max_decel: [-1.0, 0.0, -3.2]\n'
                      '    velocity_timeout: 0.5\n    use_realtime_priority: false\n')
    smoother = spawn.node('nav2_velocity_smoother', 'velocity_smoother', '--ros-args', '--params-file', params,
                          '-r', 'cmd_vel:=cmd_vel_nav', '-r', 'cmd_vel_smoothed:=cmd_vel')
    node = probe
    activate(node, 'velocity_smoother', smoother)

    out: list = []
    node.create_subscription(Twist, 'cmd_vel', out.append, 10)
    pub = node.create_publisher(Twist, 'cmd_vel_nav', 1)
    command = Twist()
    command.linear.x, command.angular.z = 0.5, 0.5

    def commanding() -> bool:
        pub.publish(command)
        return any(abs(t.linear.x - 0.26) < 1e-9 for t in out)
    wait_until(commanding, 10, interval=0.05, message='cmd_vel reaching max_velocity from cmd_vel_nav')
    speeds = [t.linear.x for t in out]
    assert speeds[0] <= 1.0 / 20.0 + 1e-9                       # ramped up at max_accel, not jumped
    assert all(b - a <= 1.0 / 20.0 + 1e-9 for a, b in zip(speeds, speeds[1:]))
    assert all(t.angular.z == pytest.approx(0.5) for t in out[-3:])
    wait_until(lambda: out[-1].linear.x == 0.0 and out[-1].angular.z == 0.0, 10,
               message='a zero command after velocity_timeout without input')
