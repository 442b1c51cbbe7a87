"""SLAM for Nav2, as nav2_bringup's slam_launch.py: slam_toolbox's online_sync_launch.py with
the same use_sim_time (it maps and publishes map -> odom; no map_server, no AMCL).
    zros launch nav2_bringup slam_launch.py use_sim_time:=True
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration


def generate_launch_description():
    slam_launch = os.path.join(get_package_share_directory('slam_toolbox'), 'launch', 'online_sync_launch.py')
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('params_file', default_value='', description='Unused here: slam_toolbox has its own'),
        DeclareLaunchArgument('autostart', default_value='true', description='Unused here'),
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace (unused by zros)'),
        DeclareLaunchArgument('use_respawn', default_value='False', description='Unused here'),
        DeclareLaunchArgument('log_level', default_value='info', description='Unused here'),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(slam_launch),
                                 launch_arguments={'use_sim_time': LaunchConfiguration('use_sim_time')}.items()),
    ])
