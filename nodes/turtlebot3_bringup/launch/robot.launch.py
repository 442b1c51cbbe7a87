"""The robot's half of a two-machine TurtleBot3: its drivers and robot_state_publisher, as
turtlebot3_bringup's robot.launch.py runs them on the real robot's computer. Here the drivers
are the simulator (gzserver: wheels, lidar, IMU, odometry) in turtlebot3_world.
    export TURTLEBOT3_MODEL=burger
    ZROS_CONFIG=configs/zenoh/client.json5 ZROS_CONNECT=tcp/<laptop>:7447 \
        zros launch turtlebot3_bringup robot.launch.py
The other half is laptop.launch.py; docs/multi-machine.md ("A robot on Wi-Fi") sets both up.

Unlike Gazebo's plugin, the base stops by itself when cmd_vel stops coming: `cmd_vel_timeout`
defaults to 0.5 s, the OpenCR board's value (its ROS 1 firmware zeroes the wheels after 500 ms
without cmd_vel; its ROS 2 firmware after 500 ms without the driver's heartbeat). A robot that
loses its Wi-Fi mid-goal then stops within half a second instead of driving on. `0` turns it off.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, GroupAction, IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import SetParameter

#: [s] without cmd_vel before the base stops: OpenCR's CONTROL_MOTOR_TIMEOUT / HEARTBEAT_TIMEOUT_MS
BASE_TIMEOUT = '0.5'


def generate_launch_description():
    gazebo = os.path.join(get_package_share_directory('turtlebot3_gazebo'), 'launch')
    return LaunchDescription([
        DeclareLaunchArgument('world', default_value='turtlebot3_world', description='The world the robot is in'),
        DeclareLaunchArgument('x_pose', default_value='-2.0', description='Where the robot starts, in metres'),
        DeclareLaunchArgument('y_pose', default_value='-0.5', description='Where the robot starts, in metres'),
        DeclareLaunchArgument('cmd_vel_timeout', default_value=BASE_TIMEOUT,
                              description='Seconds without cmd_vel before the base stops (0: never)'),
        GroupAction([
            SetParameter('cmd_vel_timeout', LaunchConfiguration('cmd_vel_timeout')),
            IncludeLaunchDescription(
                PythonLaunchDescriptionSource(os.path.join(gazebo, 'robot_world.launch.py')),
                launch_arguments={name: LaunchConfiguration(name) for name in ('world', 'x_pose', 'y_pose')}.items()),
        ]),
    ])
