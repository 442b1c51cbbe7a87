"""xacro and robot_state_publisher as processes (the URDF model and xacro expansion:
tests/unit/test_urdf.py)."""
from __future__ import annotations

import math
import os
import sys
import textwrap
import time
from pathlib import Path

import pytest

from unit.test_urdf import TWO_WHEELER
from conftest import assert_clean_failure, run_cli, wait_until
from zros.urdf import parse_urdf

BOX_LAUNCH = """
from zros.launch import LaunchDescription
from zros.launch.substitutions import Command, FindExecutable, PathJoinSubstitution
from zros.launch_ros.actions import Node
from zros.launch_ros.parameter_descriptions import ParameterValue
from zros.launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    robot_description = ParameterValue(Command([
        PathJoinSubstitution([FindExecutable(name='xacro')]), ' ',
        PathJoinSubstitution([FindPackageShare('rviz_models'), 'urdf', 'box.xacro'])]), value_type=str)
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='robot_state_publisher',
             output='screen', parameters=[{'robot_description': robot_description}]),
        Node(package='rviz2', executable='rviz2', name='rviz2', output='screen',
             arguments=['-d', PathJoinSubstitution([FindPackageShare('rviz_models'), 'rviz', 'config.rviz'])]),
    ])
"""


def test_xacro_command_line(tmp_path, zros_cli):
    import subprocess
    source = tmp_path / 'robot.urdf.xacro'
    source.write_text(TWO_WHEELER.replace('<xacro:include filename="$(find turtlebot3_description)/urdf/'
                                          'turtlebot3_burger.urdf" ns="unused"/>', ''))
    shell = subprocess.run([str(Path(sys.executable).parent / 'xacro'), str(source), 'track:=0.3'],
                           capture_output=True, text=True, timeout=30)
    assert shell.returncode == 0, shell.stderr
    assert parse_urdf(shell.stdout).joints['left_wheel_joint'].origin.xyz[1] == pytest.approx(0.15)
    missing = zros_cli('run', 'xacro', 'xacro', str(tmp_path / 'missing.xacro'))
    assert_clean_failure(missing, 'xacro: error:', 'No such file or directory')
    bad = tmp_path / 'bad.xacro'
    bad.write_text('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:wheel side="l"/></robot>')
    assert_clean_failure(zros_cli('run', 'xacro', 'xacro', str(bad)), 'bad.xacro', 'unknown macro name: xacro:wheel')


def test_robot_state_publisher_from_a_launch_file(tmp_path, spawn, make_context, monkeypatch):
    """Launch runs `xacro` into robot_description; joint_states move the wheels on /tf, fixed
    joints arrive on /tf_static, /robot_description reaches a late subscriber."""
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.tf2_ros import Buffer, Time, TransformListener
    from interfaces.sensor_msgs.msg import JointState
    from interfaces.std_msgs.msg import String
    source = tmp_path / 'robot.urdf.xacro'
    source.write_text(TWO_WHEELER.replace('<xacro:include filename="$(find turtlebot3_description)/urdf/'
                                          'turtlebot3_burger.urdf" ns="unused"/>', ''))
    launch_file = tmp_path / 'robot.launch.yaml'
    launch_file.write_text(textwrap.dedent(f'''\
        launch:
        - node:
            pkg: robot_state_publisher
            exec: robot_state_publisher
            output: screen
            param:
            - {{name: robot_description, value: "$(command 'xacro {source} track:=0.3')"}}
        '''))
    launch = spawn(sys.executable, '-m', 'zros.cli.main', 'launch', str(launch_file), name='launch')
    launch.wait_for_output("Robot 'two_wheeler': 4 links, 1 fixed joints", timeout=30)
    context = make_context()
    node = Node('rsp_test', context=context)
    buffer = Buffer()
    TransformListener(buffer, node)
    assert buffer.can_transform('base_link', 'laser', Time(), timeout=10)
    laser = buffer.lookup_transform('base_link', 'laser', Time()).transform
    assert (laser.translation.x, laser.translation.z) == pytest.approx((0.1, 0.2))
    states = node.create_publisher(JointState, 'joint_states', 10)
    wait_until(lambda: node.count_subscribers('joint_states') >= 1, 10, message='rsp subscribed to joint_states')
    msg = JointState(name=['left_wheel_joint', 'right_wheel_joint'], position=[math.pi / 2, -0.5])
    msg.header.stamp.sec = 42

    def arrived() -> bool:
        states.publish(msg)
        return buffer.can_transform('base_link', 'left_wheel', Time(seconds=42), timeout=0.2)
    wait_until(arrived, 10, message='wheel transforms at t=42 s')
    left = buffer.lookup_transform('base_link', 'left_wheel', Time(seconds=42)).transform
    right = buffer.lookup_transform('base_link', 'right_wheel', Time(seconds=42)).transform
    assert (left.translation.y, left.translation.z) == pytest.approx((0.15, 0.05))
    assert right.translation.y == pytest.approx(-0.15)
    assert (left.rotation.y, left.rotation.w) == pytest.approx((math.sin(math.pi / 4), math.cos(math.pi / 4)))
    assert (right.rotation.y, right.rotation.w) == pytest.approx((math.sin(-0.25), math.cos(-0.25)))
    received = []
    node.create_subscription(String, 'robot_description', received.append,
                             QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    from zros.executors import SingleThreadedExecutor
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    deadline = time.monotonic() + 10
    while not received and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert received and 'two_wheeler' in received[0].data


def test_the_seeds_xacro_launch_pattern_finds_xacro_without_an_activated_venv(tmp_path):
    """Seed 004's box.launch.py: `Command([FindExecutable(name='xacro'), ' ', path])` into
    `ParameterValue(..., value_type=str)`, with zros's `xacro` found next to its interpreter when
    the venv's bin directory is not on PATH (as when `.venv/bin/zros` is run directly)."""
    package = tmp_path / 'ws' / 'rviz_models'
    for folder in ('urdf', 'rviz', 'launch'):
        (package / folder).mkdir(parents=True)
    (package / 'urdf' / 'box.xacro').write_text(
        '<?xml version="1.0"?>\n<robot name="box_robot" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:property name="side" value="1"/><link name="world"/>'
        '<link name="base_link"><visual><geometry><box size="${side} ${side} ${side}"/></geometry></visual></link>'
        '<joint name="world_to_base" type="fixed"><parent link="world"/><child link="base_link"/></joint></robot>\n')
    (package / 'rviz' / 'config.rviz').write_text('Visualization Manager:\n  Global Options:\n    Fixed Frame: world\n')
    (package / 'launch' / 'box.launch.py').write_text(BOX_LAUNCH)
    env = {**os.environ, 'ZROS_NODE_PATH': str(tmp_path / 'ws'), 'PATH': '/usr/bin:/bin'}
    plan = run_cli('launch', 'rviz_models', 'box.launch.py', '--print', '--log-dir', tmp_path / 'log',
                   env=env, timeout=60)
    assert plan.returncode == 0, plan
    assert '<box size=\\"1 1 1\\"/>' in plan.stdout and 'box_robot' in plan.stdout, plan
    assert f"-d {package / 'rviz' / 'config.rviz'}" in plan.stdout, plan


def test_robot_state_publisher_refuses_a_bad_description(zros_cli):
    result = zros_cli('run', 'robot_state_publisher', 'robot_state_publisher', '--ros-args', '-p',
                      'robot_description:=<robot name="x"><link name="a"/><joint name="j" type="fixed">'
                      '<parent link="a"/></joint></robot>')
    assert_clean_failure(result, "<joint name='j'>: missing <child link")
    assert_clean_failure(zros_cli('run', 'robot_state_publisher', 'robot_state_publisher'), 'robot_description')
