"""Gazebo Sim's side (ros_gz_sim, ros_gz_bridge, nav2_minimal_tb3_sim) as real processes: a launch
file in the shape of Nav2 Jazzy's tb3_simulation_launch.py's simulation half gives /scan, /odom,
/tf, /clock and a robot that moves on /cmd_vel; without the bridge there is no /scan, as in Gazebo."""
from __future__ import annotations

import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from conftest import assert_clean_failure, wait_until

# The simulation half of tb3_simulation_launch.py (Jazzy), as a user writes it: unported imports,
# ros_gz_sim's gz_sim.launch.py on a world that xacro made, nav2_minimal_tb3_sim's spawn_tb3
# (bridge + create) and robot_state_publisher on the package's URDF.
SIM_LAUNCH = '''
import os
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    sim_dir = get_package_share_directory('nav2_minimal_tb3_sim')
    with open(os.path.join(sim_dir, 'urdf', 'turtlebot3_waffle.urdf')) as infp:
        robot_description = infp.read()
    gz_sim = os.path.join(get_package_share_directory('ros_gz_sim'), 'launch', 'gz_sim.launch.py')
    return LaunchDescription([
        DeclareLaunchArgument('world_sdf'),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(gz_sim),
                                 launch_arguments={'gz_args': ['-r -s ', LaunchConfiguration('world_sdf')]}.items()),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(os.path.join(sim_dir, 'launch', 'spawn_tb3.launch.py')),
            launch_arguments={'use_sim_time': 'true', 'robot_name': 'turtlebot3_waffle',
                              'x_pose': '-2.00', 'y_pose': '-0.50'}.items()),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='robot_state_publisher',
             parameters=[{'use_sim_time': True, 'robot_description': robot_description}],
             remappings=[('/tf', 'tf'), ('/tf_static', 'tf_static')]),
    ])
'''


def xacro_world(tmp_path: Path, package: str, world_file: str) -> Path:
    """A package's world through xacro (headless), as Nav2's tb3/tb4 launch files do before `gz sim`."""
    from zros.ament_index_python.packages import get_package_share_directory
    world = tmp_path / 'nav2_world.sdf'
    source = Path(get_package_share_directory(package)) / 'worlds' / world_file
    subprocess.run([str(Path(sys.executable).parent / 'xacro'), '-o', str(world), 'headless:=True', str(source)],
                   check=True, timeout=60)
    return world


def sandbox_world(tmp_path: Path) -> Path:
    return xacro_world(tmp_path, 'nav2_minimal_tb3_sim', 'tb3_sandbox.sdf.xacro')


class Listener:
    """Keeps what arrives on a few topics, on its own executor thread."""

    def __init__(self, context: Any, topics: dict[str, type]) -> None:
        from zros.executors import MultiThreadedExecutor
        from zros.node import Node
        self.node = Node('gz_test', context=context)
        self.received: dict[str, list[Any]] = {topic: [] for topic in topics}
        for topic, msg_type in topics.items():
            self.node.create_subscription(msg_type, topic, self.received[topic].append, 50)
        self.executor = MultiThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        threading.Thread(target=self.executor.spin, daemon=True).start()

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=2)


def drive_forward(listener: Listener, speed: float, distance: float, launch: Any) -> None:
    """Publish `speed` on /cmd_vel until /odom (which `listener` keeps) has gone `distance` along x."""
    from interfaces.geometry_msgs.msg import Twist
    odom = listener.received['/odom']
    cmd = listener.node.create_publisher(Twist, '/cmd_vel', 10)
    start = odom[-1].pose.pose.position.x
    forward = Twist()
    forward.linear.x = speed

    def moved() -> bool:
        cmd.publish(forward)
        time.sleep(0.2)
        return odom[-1].pose.pose.position.x > start + distance
    wait_until(moved, 120, message=lambda: f'the robot did not move\n{launch.output()}')


@pytest.mark.timeout(600)
def test_the_tb3_simulation_half_gives_the_robots_topics_and_it_drives(spawn: Any, context: Any,
                                                                        tmp_path: Path) -> None:
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.rosgraph_msgs.msg import Clock
    from interfaces.sensor_msgs.msg import JointState, LaserScan
    from interfaces.tf2_msgs.msg import TFMessage
    launch_file = tmp_path / 'tb3_simulation_half.launch.py'
    launch_file.write_text(SIM_LAUNCH)
    launch = spawn.launch(launch_file, f'world_sdf:={sandbox_world(tmp_path)}')
    listener = Listener(context, {'/scan': LaserScan, '/odom': Odometry, '/tf': TFMessage, '/clock': Clock,
                                  '/joint_states': JointState, '/tf_static': TFMessage})
    try:
        got = listener.received
        for topic in ('/clock', '/scan', '/odom', '/tf', '/joint_states'):
            wait_until(lambda: got[topic], 240, message=lambda: f'no {topic}\n{launch.output()}')
        scan = got['/scan'][-1]
        # The numbers of the model's gpu_lidar (gz_waffle.sdf.xacro), not the burger's LDS-01.
        assert (len(scan.ranges), scan.range_max, scan.header.frame_id) == (360, 20.0, 'base_scan')
        odom = got['/odom'][-1]
        assert (odom.header.frame_id, odom.child_frame_id) == ('odom', 'base_footprint')
        assert any(t.header.frame_id == 'odom' and t.child_frame_id == 'base_footprint'
                   for m in got['/tf'] for t in m.transforms)
        assert list(got['/joint_states'][-1].name) == ['wheel_left_joint', 'wheel_right_joint']
        # The world of the sandbox (its <world name>), the waffle where spawn_tb3's pose puts it.
        assert "World 'default'" in launch.output()
        assert "Spawned waffle 'turtlebot3_waffle' at x=-2 y=-0.5 yaw=0" in launch.output()
        # The sandbox's arena is there: facing +x from (-2, -0.5), the wall's inner face is near.
        assert 0.3 < min(r for r in scan.ranges if r == r) < 3.0
        drive_forward(listener, 0.2, 0.1, launch)
    finally:
        listener.close()


@pytest.mark.timeout(400)
def test_without_the_bridge_there_is_no_scan(spawn: Any, context: Any, tmp_path: Path) -> None:
    from interfaces.sensor_msgs.msg import LaserScan
    world = sandbox_world(tmp_path)
    sim = spawn.run('ros_gz_sim', 'gz', 'sim', '-r', '-s', str(world))
    from zros.ament_index_python.packages import get_package_share_directory
    sdf = Path(get_package_share_directory('nav2_minimal_tb3_sim')) / 'urdf' / 'gz_waffle.sdf.xacro'
    robot = tmp_path / 'waffle.sdf'
    subprocess.run([str(Path(sys.executable).parent / 'xacro'), '-o', str(robot), str(sdf)], check=True, timeout=60)
    create = spawn.run('ros_gz_sim', 'create', '-name', 'turtlebot3_waffle', '-file', str(robot), '-x', '-2.0')
    assert create.wait(240) == 0, f'{create.output()}\n{sim.output()}'
    listener = Listener(context, {'/scan': LaserScan, '/_gz/scan': LaserScan})
    try:
        wait_until(lambda: listener.received['/_gz/scan'], 120, message=lambda: f'no Gazebo-side scan\n{sim.output()}')
        time.sleep(1.0)
        assert listener.received['/scan'] == []     # Gazebo's topic, not yet a ROS one
        bridge = spawn.run('ros_gz_bridge', 'parameter_bridge', 'scan@sensor_msgs/msg/LaserScan[gz.msgs.LaserScan')
        wait_until(lambda: listener.received['/scan'], 120, message=lambda: f'no /scan\n{bridge.output()}')
    finally:
        listener.close()


def test_bad_command_lines_are_one_line(domain: int, tmp_path: Path, zros_cli: Any) -> None:
    result = zros_cli('run', 'ros_gz_sim', 'gz', 'topic', '-l', timeout=60)
    assert_clean_failure(result, "'gz topic': zros plays only 'gz sim'")
    result = zros_cli('run', 'ros_gz_sim', 'create', '-name', 'x', timeout=60)
    assert_clean_failure(result, 'Must specify either -file, -param, -string or -topic')
    bad = tmp_path / 'bridge.yaml'
    bad.write_text('- {topic_name: scan, ros_type_name: sensor_msgs/msg/Imu, gz_type_name: gz.msgs.LaserScan}\n')
    result = zros_cli('run', 'ros_gz_bridge', 'parameter_bridge', '--ros-args', '-p', f'config_file:={bad}',
                      timeout=60)
    assert_clean_failure(result, f'{bad}: entry 1: no bridge between ROS type sensor_msgs/msg/Imu and Gazebo type '
                                 'gz.msgs.LaserScan')
