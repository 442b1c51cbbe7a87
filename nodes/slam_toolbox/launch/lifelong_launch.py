"""slam_toolbox's lifelong launch file: zros's SLAM mapping on in a saved pose graph
(`map_file_name` in config/mapper_params_lifelong.yaml; docs/slam.md).
    zros launch slam_toolbox lifelong_launch.py
"""
from zros.launch import LaunchDescription
from zros.launch_ros.actions import Node
from zros.launch_ros.substitutions import FindPackageShare
from zros.launch.substitutions import PathJoinSubstitution


def generate_launch_description():
    return LaunchDescription([
        Node(package='slam_toolbox', executable='lifelong_slam_toolbox_node', name='slam_toolbox', output='screen',
             parameters=[PathJoinSubstitution([FindPackageShare('slam_toolbox'), 'config',
                                               'mapper_params_lifelong.yaml'])]),
    ])
