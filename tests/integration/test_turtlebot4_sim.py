"""Nav2 Jazzy's TurtleBot4 in Gazebo Sim, as real processes: a launch file in the shape of
tb4_simulation_launch.py's simulation half (the depot world through xacro and `gz sim`,
nav2_minimal_tb4_sim's spawn_tb4 spawning from robot_state_publisher's robot_description, that
robot_state_publisher on `xacro turtlebot4.urdf.xacro`) gives the RPLIDAR's /scan in rplidar_link,
/odom from odom to base_link, and a robot that drives on /cmd_vel; tb4_loopback_simulation's robot
scans the depot map from its turned lidar."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import wait_until
from integration.test_ros_gz_sim import Listener, drive_forward, xacro_world

# As tb4_simulation_launch.py writes it (unported imports): the world is xacro'd to a file first,
# then `gz sim -r -s` runs it; the robot comes from the robot_description topic.
SIM_LAUNCH = '''
import os
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import Command, LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    sim_dir = get_package_share_directory('nav2_minimal_tb4_sim')
    desc_dir = get_package_share_directory('nav2_minimal_tb4_description')
    robot_sdf = os.path.join(desc_dir, 'urdf', 'standard', 'turtlebot4.urdf.xacro')
    return LaunchDescription([
        DeclareLaunchArgument('world_sdf'),
        ExecuteProcess(cmd=['gz', 'sim', '-r', '-s', LaunchConfiguration('world_sdf')], output='screen'),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(os.path.join(sim_dir, 'launch', 'spawn_tb4.launch.py')),
            launch_arguments={'use_sim_time': 'true', 'robot_name': 'nav2_turtlebot4', 'x_pose': '-8.00',
                              'y_pose': '0.00', 'z_pose': '0.01'}.items()),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='robot_state_publisher',
             parameters=[{'use_sim_time': True, 'robot_description': Command(['xacro', ' ', robot_sdf])}],
             remappings=[('/tf', 'tf'), ('/tf_static', 'tf_static')]),
    ])
'''


@pytest.mark.timeout(600)
def test_the_tb4_simulation_half_gives_the_robots_topics_and_it_drives(spawn: Any, context: Any,
                                                                        tmp_path: Path) -> None:
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.sensor_msgs.msg import LaserScan
    from interfaces.tf2_msgs.msg import TFMessage
    # listening first: the robot's first messages and the latched /tf_static are all kept
    listener = Listener(context, {'/scan': LaserScan, '/odom': Odometry, '/tf': TFMessage, '/tf_static': TFMessage})
    world = xacro_world(tmp_path, 'nav2_minimal_tb4_sim', 'depot.sdf')
    (tmp_path / 'tb4_simulation_half.launch.py').write_text(SIM_LAUNCH)
    try:
        launch = spawn.launch(tmp_path / 'tb4_simulation_half.launch.py', f'world_sdf:={world}')
        got = listener.received
        for topic in ('/scan', '/odom', '/tf', '/tf_static'):
            wait_until(lambda: got[topic], 240, message=lambda: f'no {topic}\n{launch.output()}')
        # the simulator's log line may reach the launch's output after its first messages (a busy machine)
        spawned = "Spawned turtlebot4 'nav2_turtlebot4' at x=-8 y=0 yaw=0"
        wait_until(lambda: spawned in launch.output(), 30, message=lambda: f'no spawn line\n{launch.output()}')
        scan = got['/scan'][-1]
        # The RPLIDAR A1 of the description, in its own frame (turned a quarter turn left).
        assert (len(scan.ranges), scan.range_min, scan.range_max, scan.header.frame_id) == \
            (360, pytest.approx(0.164), 20.0, 'rplidar_link')
        # From (-8, 0) facing +x: the depot's west wall (inner face x = -14.8) is behind, at
        # the beam that rplidar_link calls +90 degrees; ahead (its -90 degrees) a pallet at x = 6.4.
        behind, ahead = (round((angle - scan.angle_min) / scan.angle_increment) for angle in (math.pi / 2, 1.5 * math.pi))
        assert scan.ranges[behind] == pytest.approx(6.76, abs=0.1)
        assert scan.ranges[ahead] == pytest.approx(14.44, abs=0.1)
        # ... at its update_rate: 10 Hz of simulated time (the TurtleBot3's LDS-01 gives 5)
        wait_until(lambda: len(got['/scan']) >= 3, 60, message=lambda: f'scans stopped\n{launch.output()}')
        stamps = [m.header.stamp.sec + m.header.stamp.nanosec * 1e-9 for m in got['/scan'][-3:]]
        assert stamps[2] - stamps[1] == pytest.approx(0.1, abs=0.006)
        odom = got['/odom'][-1]
        assert (odom.header.frame_id, odom.child_frame_id) == ('odom', 'base_link')
        assert any(t.child_frame_id == 'rplidar_link' for m in got['/tf_static'] for t in m.transforms)
        drive_forward(listener, 0.3, 0.2, launch)
    finally:
        listener.close()


# tb4_loopback_simulation.launch.py's robot and simulator, as it writes them (its Nav2 bringup
# left out): robot_state_publisher on the TurtleBot4, its static base_footprint -> base_link,
# the depot map served, and nav2_loopback_sim scanning in rplidar_link.
LOOPBACK_LAUNCH = '''
import os
from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import Command
from launch_ros.actions import Node


def generate_launch_description():
    bringup_dir = get_package_share_directory('nav2_bringup')
    loopback_sim_dir = get_package_share_directory('nav2_loopback_sim')
    desc_dir = get_package_share_directory('nav2_minimal_tb4_description')
    sdf = os.path.join(desc_dir, 'urdf', 'standard', 'turtlebot4.urdf.xacro')
    params_file = os.path.join(bringup_dir, 'params', 'nav2_params.yaml')
    return LaunchDescription([
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='robot_state_publisher',
             parameters=[{'use_sim_time': True, 'robot_description': Command(['xacro', ' ', sdf])}],
             remappings=[('/tf', 'tf'), ('/tf_static', 'tf_static')]),
        Node(package='tf2_ros', executable='static_transform_publisher',
             arguments=['0.0', '0.0', '0.0', '0', '0', '0', 'base_footprint', 'base_link']),
        Node(package='nav2_map_server', executable='map_server', name='map_server',
             parameters=[{'use_sim_time': True,
                          'yaml_filename': os.path.join(bringup_dir, 'maps', 'depot.yaml')}]),
        Node(package='nav2_lifecycle_manager', executable='lifecycle_manager', name='lifecycle_manager_map_server',
             parameters=[{'use_sim_time': True, 'autostart': True, 'node_names': ['map_server']}]),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(os.path.join(loopback_sim_dir, 'loopback_simulation.launch.py')),
            launch_arguments={'params_file': params_file, 'scan_frame_id': 'rplidar_link'}.items()),
    ])
'''


@pytest.mark.timeout(400)
def test_the_tb4_loopback_robot_scans_the_depot_map_from_its_turned_lidar(spawn: Any, probe: Any,
                                                                          tmp_path: Path) -> None:
    from zros.ament_index_python.packages import get_package_share_directory
    from zros.map_io import load_map
    from zros.qos import qos_profile_sensor_data
    from zros.sim.grid_lidar import GridLidar
    from zros.tf2_ros import Buffer, TransformListener
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped
    from interfaces.sensor_msgs.msg import LaserScan
    from integration.test_loopback_sim import _initial_pose, _map_to_base
    scans: list = []
    probe.create_subscription(LaserScan, 'scan', scans.append, qos_profile_sensor_data)
    buffer = Buffer()
    TransformListener(buffer, probe)
    place = probe.create_publisher(PoseWithCovarianceStamped, 'initialpose', 10)
    (tmp_path / 'tb4_loopback.launch.py').write_text(LOOPBACK_LAUNCH)
    launch = spawn.launch(tmp_path / 'tb4_loopback.launch.py')
    # The depot map's frame starts where the robot does: (0, 0) facing +x.
    wait_until(lambda: (place.publish(_initial_pose(probe, 0.0, 0.0, 0.0)) or True) and _map_to_base(buffer), 120,
               interval=0.5, message=lambda: f'map -> base_footprint\n{launch.output()}')
    wait_until(lambda: scans and np.isfinite(scans[-1].ranges).sum() > 100, 60,
               message=lambda: f'a scan of the depot\n{launch.output()}')
    scan = scans[-1]
    assert scan.header.frame_id == 'rplidar_link'
    grid = load_map(Path(get_package_share_directory('nav2_bringup')) / 'maps' / 'depot.yaml')
    lidar = GridLidar(grid.data, grid.geometry)
    expected = lidar.scan((-0.04, 0.0, math.pi / 2), scan.angle_min, scan.angle_increment, len(scan.ranges),
                          scan.range_max)
    assert np.allclose(np.asarray(scan.ranges), expected, rtol=1e-4)
