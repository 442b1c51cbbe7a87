"""TurtleBot3's navigation: Nav2 (nav2_bringup's bringup_launch.py) with this package's map and
parameters, and the view (rviz2 with nav2_default_view.rviz), as turtlebot3_navigation2's
navigation2.launch.py:
    export TURTLEBOT3_MODEL=burger
    zros launch turtlebot3_navigation2 navigation2.launch.py use_sim_time:=True map:=$HOME/map.yaml
    zros launch turtlebot3_navigation2 navigation2.launch.py use_sim_time:=True slam:=True
`map` defaults to the shipped turtlebot3_world map (map/map.yaml), `params_file` to
param/$TURTLEBOT3_MODEL.yaml (burger when unset; param/humble/ when ROS_DISTRO is humble, as
upstream's); the view is rviz2 with rviz/tb3_navigation2.rviz, and `rviz:=false` leaves it out.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.conditions import IfCondition
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    model = os.environ.get('TURTLEBOT3_MODEL', 'burger')
    share = get_package_share_directory('turtlebot3_navigation2')
    bringup = get_package_share_directory('nav2_bringup')
    param_dir = os.path.join(share, 'param', 'humble') if os.environ.get('ROS_DISTRO') == 'humble' else \
        os.path.join(share, 'param')
    params = os.path.join(param_dir, f'{model}.yaml')
    if not os.path.exists(params):
        params = os.path.join(param_dir, 'burger.yaml')
    use_sim_time = LaunchConfiguration('use_sim_time')
    return LaunchDescription([
        DeclareLaunchArgument('map', default_value=os.path.join(share, 'map', 'map.yaml'),
                              description='Full path to map file to load'),
        DeclareLaunchArgument('params_file', default_value=params, description='Full path to param file to load'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('slam', default_value='False', description='Whether run a SLAM instead of map + AMCL'),
        DeclareLaunchArgument('rviz', default_value='true', description='Whether to start the view (rviz2)'),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(os.path.join(bringup, 'launch', 'bringup_launch.py')),
            launch_arguments={'map': LaunchConfiguration('map'), 'use_sim_time': use_sim_time,
                              'params_file': LaunchConfiguration('params_file'),
                              'slam': LaunchConfiguration('slam')}.items()),
        Node(package='rviz2', executable='rviz2', name='rviz2', output='screen',
             arguments=['-d', os.path.join(share, 'rviz', 'tb3_navigation2.rviz')],
             parameters=[{'use_sim_time': use_sim_time}], condition=IfCondition(LaunchConfiguration('rviz'))),
    ])
