"""Nav2's navigation servers under one lifecycle manager, as nav2_bringup's navigation_launch.py:
    zros launch nav2_bringup navigation_launch.py use_sim_time:=True params_file:=/path/to/params.yaml
`params_file` defaults to nav2_bringup's params/nav2_params.yaml (Nav2's numbers for a waffle; a
burger wants turtlebot3_navigation2's param/burger.yaml). controller_server, planner_server, behavior_server, bt_navigator and waypoint_follower, brought
up in that order by lifecycle_manager_navigation (autostart). Nav2's smoother_server and
velocity_smoother are left out here (the planner smooths its paths; the controller limits its
own accelerations and publishes `cmd_vel` itself); zros has them for Nav2's own launch file,
which remaps the controller to `cmd_vel_nav`. See docs/navigation.md.
Nav2's other arguments are taken: `use_respawn` and `log_level` apply to every server;
`use_composition` and `container_name` are read and change nothing (one process per server).
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node

LIFECYCLE_NODES = ['controller_server', 'planner_server', 'behavior_server', 'bt_navigator', 'waypoint_follower']


def generate_launch_description():
    default_params = os.path.join(get_package_share_directory('nav2_bringup'), 'params', 'nav2_params.yaml')
    use_sim_time = LaunchConfiguration('use_sim_time')
    params_file = LaunchConfiguration('params_file')
    autostart = LaunchConfiguration('autostart')
    common = [params_file, {'use_sim_time': use_sim_time}]
    servers = [('nav2_controller', 'controller_server'), ('nav2_planner', 'planner_server'),
               ('nav2_behaviors', 'behavior_server'), ('nav2_bt_navigator', 'bt_navigator'),
               ('nav2_waypoint_follower', 'waypoint_follower')]
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace (unused by zros)'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('params_file', default_value=default_params,
                              description='Full path to the ROS2 parameters file to use for all launched nodes'),
        DeclareLaunchArgument('autostart', default_value='true', description='Automatically startup the nav2 stack'),
        DeclareLaunchArgument('use_composition', default_value='False', description='Unused by zros'),
        DeclareLaunchArgument('container_name', default_value='nav2_container', description='Unused by zros'),
        DeclareLaunchArgument('use_respawn', default_value='False', description='Whether to respawn if a node crashes'),
        DeclareLaunchArgument('log_level', default_value='info', description='log level'),
        *[Node(package=package, executable=executable, name=executable, output='screen', parameters=common,
               respawn=LaunchConfiguration('use_respawn'), respawn_delay=2.0,
               arguments=['--ros-args', '--log-level', LaunchConfiguration('log_level')])
          for package, executable in servers],
        Node(package='nav2_lifecycle_manager', executable='lifecycle_manager', name='lifecycle_manager_navigation',
             output='screen',
             parameters=[{'use_sim_time': use_sim_time, 'autostart': autostart, 'node_names': LIFECYCLE_NODES}]),
    ])
