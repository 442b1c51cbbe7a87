"""Map server and AMCL under one lifecycle manager, as nav2_bringup's localization_launch.py:
    zros launch nav2_bringup localization_launch.py map:=$HOME/map.yaml use_sim_time:=True
`map` is the map's YAML file; AMCL's parameters come from `params_file` (its `amcl:` section;
nav2_bringup's params/nav2_params.yaml by default). `use_respawn` and `log_level` apply to both
nodes; `use_composition` and `container_name` are read and change nothing.
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
    bringup = get_package_share_directory('nav2_bringup')
    server = {'output': 'screen', 'respawn': LaunchConfiguration('use_respawn'), 'respawn_delay': 2.0,
              'arguments': ['--ros-args', '--log-level', LaunchConfiguration('log_level')]}
    use_sim_time = LaunchConfiguration('use_sim_time')
    params_file = LaunchConfiguration('params_file')
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace (unused by zros)'),
        DeclareLaunchArgument('map', default_value=os.path.join(share, 'map', 'map.yaml'),
                              description='Full path to map yaml file to load'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('params_file', default_value=os.path.join(bringup, 'params', 'nav2_params.yaml'),
                              description='Full path to the ROS2 parameters file to use for all launched nodes'),
        DeclareLaunchArgument('autostart', default_value='true', description='Automatically startup the nav2 stack'),
        DeclareLaunchArgument('use_composition', default_value='False', description='Unused by zros'),
        DeclareLaunchArgument('container_name', default_value='nav2_container', description='Unused by zros'),
        DeclareLaunchArgument('use_respawn', default_value='False', description='Whether to respawn if a node crashes'),
        DeclareLaunchArgument('log_level', default_value='info', description='log level'),
        Node(package='nav2_map_server', executable='map_server', name='map_server', **server,
             parameters=[params_file, {'use_sim_time': use_sim_time, 'yaml_filename': LaunchConfiguration('map')}]),
        Node(package='nav2_amcl', executable='amcl', name='amcl', **server,
             parameters=[params_file, {'use_sim_time': use_sim_time}]),
        Node(package='nav2_lifecycle_manager', executable='lifecycle_manager', name='lifecycle_manager_localization',
             output='screen',
             parameters=[{'use_sim_time': use_sim_time, 'autostart': LaunchConfiguration('autostart'),
                          'node_names': LIFECYCLE_NODES}]),
    ])
