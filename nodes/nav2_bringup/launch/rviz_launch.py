"""The view with Nav2's display configuration, as nav2_bringup's rviz_launch.py (which
tb3_simulation_launch.py and tb3_loopback_simulation.launch.py include):
    zros launch nav2_bringup rviz_launch.py
    zros launch nav2_bringup rviz_launch.py rviz_config:=my_view.rviz use_sim_time:=True
`rviz_config` defaults to rviz/nav2_default_view.rviz; `namespace` and `use_namespace` are read
and change nothing (zros's view shows the un-namespaced topics).
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


#: (name, default, description) of Nav2's arguments that need nothing more here.
PLAIN_ARGUMENTS = (('namespace', '', 'Top-level namespace (unused by zros)'),
                   ('use_namespace', 'false', 'Unused by zros'),
                   ('use_sim_time', 'false', 'Use simulation (Gazebo) clock if true'))


def generate_launch_description():
    default_view = os.path.join(get_package_share_directory('nav2_bringup'), 'rviz', 'nav2_default_view.rviz')
    return LaunchDescription([
        *[DeclareLaunchArgument(name, default_value=default, description=text)
          for name, default, text in PLAIN_ARGUMENTS],
        DeclareLaunchArgument('rviz_config', default_value=default_view,
                              description='Full path to the RVIZ config file to use'),
        Node(package='rviz2', executable='rviz2', name='rviz2', output='screen',
             arguments=['-d', LaunchConfiguration('rviz_config')],
             parameters=[{'use_sim_time': LaunchConfiguration('use_sim_time')}]),
    ])
