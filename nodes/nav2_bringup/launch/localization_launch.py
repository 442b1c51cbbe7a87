"""Map server and AMCL under one lifecycle manager, as nav2_bringup's localization_launch.py:
    zros launch nav2_bringup localization_launch.py map:=$HOME/map.yaml use_sim_time:=True
`map` is the map's YAML file; AMCL's parameters come from `params_file` (its `amcl:` section).
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node

LIFECYCLE_NODES = ['map_server', 'amcl']


def generate_launch_description():
    share = get_package_share_directory('turtlebot3_navigation2')
    use_sim_time = LaunchConfiguration('use_sim_time')
    params_file = LaunchConfiguration('params_file')
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace (unused by zros)'),
        DeclareLaunchArgument('map', default_value=os.path.join(share, 'map', 'map.yaml'),
                              description='Full path to map yaml file to load'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('params_file', default_value=os.path.join(share, 'param', 'burger.yaml'),
                              description='Full path to the ROS2 parameters file to use for all launched nodes'),
        DeclareLaunchArgument('autostart', default_value='true', description='Automatically startup the nav2 stack'),
        Node(package='nav2_map_server', executable='map_server', name='map_server', output='screen',
             parameters=[params_file, {'use_sim_time': use_sim_time, 'yaml_filename': LaunchConfiguration('map')}]),
        Node(package='nav2_amcl', executable='amcl', name='amcl', output='screen',
             parameters=[params_file, {'use_sim_time': use_sim_time}]),
        Node(package='nav2_lifecycle_manager', executable='lifecycle_manager', name='lifecycle_manager_localization',
             output='screen',
             parameters=[{'use_sim_time': use_sim_time, 'autostart': LaunchConfiguration('autostart'),
                          'node_names': LIFECYCLE_NODES}]),
    ])
