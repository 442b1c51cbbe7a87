"""explore_lite's explore.launch.py: frontier exploration through navigate_to_pose.
    zros launch explore_lite explore.launch.py use_sim_time:=True
Needs SLAM (a growing /map and map -> odom) and the navigation servers running.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    config = os.path.join(get_package_share_directory('explore_lite'), 'config', 'params.yaml')
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Namespace for the explore node'),
        DeclareLaunchArgument('use_sim_time', default_value='true', description='Use simulation (Gazebo) clock if true'),
        Node(package='explore_lite', executable='explore', name='explore_node', namespace=LaunchConfiguration('namespace'),
             output='screen', parameters=[config, {'use_sim_time': LaunchConfiguration('use_sim_time')}],
             remappings=[('/tf', 'tf'), ('/tf_static', 'tf_static')]),
    ])
