"""Nav2's whole stack, as nav2_bringup's bringup_launch.py (what the courses' own launch files include):
    zros launch nav2_bringup bringup_launch.py use_sim_time:=True map:=$HOME/map.yaml
    zros launch nav2_bringup bringup_launch.py use_sim_time:=True slam:=True
Localization is map_server + AMCL (localization_launch.py), or with `slam:=True` SLAM
(slam_launch.py), which builds the map and publishes map -> odom itself, or with Jazzy's
`use_localization:=False` none (something else publishes map -> odom: nav2_loopback_sim in
tb3_loopback_simulation.launch.py); then navigation_launch.py. `params_file` defaults to
params/nav2_params.yaml; `use_composition`, `use_respawn` and `log_level` are passed on.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.conditions import IfCondition
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration, PythonExpression


def generate_launch_description():
    here = os.path.dirname(os.path.abspath(__file__))
    share = get_package_share_directory('turtlebot3_navigation2')
    bringup = get_package_share_directory('nav2_bringup')
    args = {name: LaunchConfiguration(name)
            for name in ('use_sim_time', 'params_file', 'autostart', 'use_composition', 'use_respawn', 'log_level')}
    localize = LaunchConfiguration('use_localization')
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace (unused by zros)'),
        DeclareLaunchArgument('use_namespace', default_value='false', description='Unused by zros'),
        DeclareLaunchArgument('slam', default_value='False', description='Whether run a SLAM'),
        DeclareLaunchArgument('map', default_value=os.path.join(share, 'map', 'map.yaml'),
                              description='Full path to map yaml file to load'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('use_localization', default_value='True',
                              description='Whether to enable localization (AMCL or SLAM) or not'),
        DeclareLaunchArgument('params_file', default_value=os.path.join(bringup, 'params', 'nav2_params.yaml'),
                              description='Full path to the ROS2 parameters file to use for all launched nodes'),
        DeclareLaunchArgument('autostart', default_value='true', description='Automatically startup the nav2 stack'),
        DeclareLaunchArgument('use_composition', default_value='True', description='Unused by zros'),
        DeclareLaunchArgument('use_respawn', default_value='False', description='Whether to respawn if a node crashes'),
        DeclareLaunchArgument('log_level', default_value='info', description='log level'),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(here, 'slam_launch.py')),
                                 condition=IfCondition(PythonExpression([localize, ' and ', LaunchConfiguration('slam')])),
                                 launch_arguments=args.items()),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(here, 'localization_launch.py')),
                                 condition=IfCondition(PythonExpression([localize, ' and not ', LaunchConfiguration('slam')])),
                                 launch_arguments={**args, 'map': LaunchConfiguration('map')}.items()),
        IncludeLaunchDescription(PythonLaunchDescriptionSource(os.path.join(here, 'navigation_launch.py')),
                                 launch_arguments=args.items()),
    ])
