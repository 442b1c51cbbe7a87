"""turtlebot3_bringup's robot.launch.py: the robot's drivers with the base's cmd_vel watchdog on.

(laptop.launch.py is turtlebot3_navigation2's navigation2.launch.py with other defaults; its
arguments are checked here, the stack itself in test_navigation_bringup.py.)
"""
from __future__ import annotations

import time


def test_robot_launch_runs_the_simulated_base_with_opencrs_timeout(domain, spawn, zros_cli, wait_for):
    spawn.launch('nodes/turtlebot3_bringup/launch/robot.launch.py')

    def timeout() -> str:
        return zros_cli('param', 'get', '/gazebo', 'cmd_vel_timeout').stdout
    wait_for(lambda: 'Double value is: 0.5' in timeout(), timeout=60, message=lambda: f'cmd_vel_timeout: {timeout()!r}')
    nodes = zros_cli('node', 'list').stdout.split()
    assert {'/gazebo', '/robot_state_publisher'} <= set(nodes), nodes
    # A single command moves the base, which stops by itself half a second later.
    zros_cli('topic', 'pub', '--once', '/cmd_vel', 'geometry_msgs/msg/Twist', '{linear: {x: 0.2}}')
    time.sleep(1.5)
    odom = zros_cli('topic', 'echo', '--once', '--timeout', '10', '/odom', 'nav_msgs/msg/Odometry', timeout=20).stdout
    twist = odom.split('twist:', 1)[1]
    assert 'x: 0.0\n' in twist.split('angular:')[0], odom


def test_laptop_launch_declares_the_laptop_defaults(zros_cli):
    shown = zros_cli('launch', 'turtlebot3_bringup', 'laptop.launch.py', '--show-args').stdout
    for name, default in (('use_sim_time', 'true'), ('view', 'false'), ('slam', 'False')):
        assert f"'{name}':" in shown and f"(default: '{default}')" in shown.split(f"'{name}':", 1)[1], shown
