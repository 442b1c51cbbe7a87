"""A student's own launch file that includes `turtlebot3_gazebo/launch/turtlebot3_world.launch.py`
the way seed 000's exploration launch file does (get_package_share_directory, use_sim_time,
x_pose, y_pose), run end to end: the world, the robot where the arguments put it,
robot_state_publisher on the shipped URDF, /scan to a plain depth-10 subscription, a whole TF
tree, and Ctrl-C. (Each shipped world file's YAML twin has the same plan: test_launch_python.)"""
from __future__ import annotations

import signal
import sys
import threading
from pathlib import Path
from typing import Any

import pytest

from conftest import wait_until

STUDENT_LAUNCH = '''
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration

TURTLEBOT3_MODEL = os.environ['TURTLEBOT3_MODEL']


def generate_launch_description():
    use_sim_time = LaunchConfiguration('use_sim_time', default='True')
    x_pose = LaunchConfiguration('x_pose', default='-2.0')
    y_pose = LaunchConfiguration('y_pose', default='-0.5')
    turtlebot3_world_cmd = IncludeLaunchDescription(
        PythonLaunchDescriptionSource([os.path.join(
            get_package_share_directory('turtlebot3_gazebo'), 'launch'), '/turtlebot3_world.launch.py']),
        launch_arguments={'use_sim_time': use_sim_time, 'x_pose': x_pose, 'y_pose': y_pose}.items())
    ld = LaunchDescription()
    ld.add_action(turtlebot3_world_cmd)
    return ld
'''


def test_a_students_launch_file_includes_turtlebot3_world(spawn: Any, context: Any, tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    from zros.executors import MultiThreadedExecutor
    from zros.node import Node
    from zros.tf2_ros import Buffer, TransformListener
    from zros.time import Time
    from interfaces.gazebo_msgs.srv import GetEntityState
    from interfaces.sensor_msgs.msg import LaserScan
    package = tmp_path / 'pkgs' / 'autonomous_exploration'
    (package / 'launch').mkdir(parents=True)
    (package / 'launch' / 'autonomous_exploration.launch.py').write_text(STUDENT_LAUNCH)
    monkeypatch.setenv('ZROS_NODE_PATH', str(tmp_path / 'pkgs'))
    monkeypatch.setenv('TURTLEBOT3_MODEL', 'burger')
    launch = spawn(sys.executable, '-m', 'zros', 'launch', 'autonomous_exploration', 'autonomous_exploration.launch.py',
                   'x_pose:=0.5', 'y_pose:=2.0', 'real_time_factor:=5.0', name='launch')
    node = Node('launch_test', context=context)
    scans = []
    node.create_subscription(LaserScan, 'scan', scans.append, 10)
    buffer = Buffer()
    TransformListener(buffer, node)
    executor = MultiThreadedExecutor(context=context)
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    try:
        client = node.create_client(GetEntityState, '/get_entity_state')
        assert client.wait_for_service(timeout_sec=30), launch.output()
        state = client.call(GetEntityState.Request(name='burger'), timeout_sec=10)
        assert state.success and (state.state.pose.position.x, state.state.pose.position.y) == (0.5, 2.0)
        wait_until(lambda: scans, 20, message=lambda: f'no /scan\n{launch.output()}')
        assert scans[0].header.frame_id == 'base_scan' and len(scans[0].ranges) == 360
        # odom -> base_footprint from the simulator, base_footprint -> ... -> base_scan from
        # robot_state_publisher: the chain students look up.
        wait_until(lambda: buffer.can_transform('odom', 'base_scan', Time()), 20,
                   message=lambda: f'odom -> base_scan; frames: {buffer.all_frames_as_string()}\n{launch.output()}')
        t = buffer.lookup_transform('odom', 'base_scan', Time()).transform.translation
        # Gazebo's world odometry: odom is the world frame, the robot where it was spawned.
        assert (t.x, t.y, t.z) == pytest.approx((0.5 - 0.032, 2.0, 0.182), abs=1e-6)
        wait_until(lambda: buffer.can_transform('base_link', 'wheel_left_link', Time()), 20,
                   message='the wheels from joint_states')
        assert 'robot_state_publisher' in {n for n, _ in node.get_node_names_and_namespaces()}
    finally:
        executor.shutdown(timeout_sec=2)
    launch.signal(signal.SIGINT)
    assert launch.wait(10) == 0, launch.output()
    assert 'process has finished cleanly' in launch.output()
