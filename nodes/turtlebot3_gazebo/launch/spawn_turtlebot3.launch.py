"""Spawn the TurtleBot3 into a running simulator, as turtlebot3_gazebo's launch file of that name.

    zros launch gazebo_ros gzserver.launch.py world:=$(...)/worlds/turtlebot3_world.world
    zros launch turtlebot3_gazebo spawn_turtlebot3.launch.py x_pose:=-2.0 y_pose:=-0.5

gazebo_ros's `spawn_entity.py` puts `models/turtlebot3_$TURTLEBOT3_MODEL/model.sdf` of this package
into the world as entity `$TURTLEBOT3_MODEL` (burger when unset) at (`x_pose`, `y_pose`, 0.01),
upstream's (Humble) arguments and defaults (0.0, 0.0). The model's plugins say what it publishes:
odometry in the world frame, `scan`, `imu`, `joint_states` (docs/robot.md).
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    model = os.environ.get('TURTLEBOT3_MODEL', 'burger') or 'burger'
    sdf = os.path.join(get_package_share_directory('turtlebot3_gazebo'), 'models', f'turtlebot3_{model}', 'model.sdf')
    return LaunchDescription([
        DeclareLaunchArgument('x_pose', default_value='0.0', description='Where the robot starts, x [m]'),
        DeclareLaunchArgument('y_pose', default_value='0.0', description='Where the robot starts, y [m]'),
        Node(package='gazebo_ros', executable='spawn_entity.py', output='screen',
             arguments=['-entity', model, '-file', sdf, '-x', LaunchConfiguration('x_pose'),
                        '-y', LaunchConfiguration('y_pose'), '-z', '0.01']),
    ])
