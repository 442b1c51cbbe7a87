"""slam_toolbox's map merging launch file: merge_maps_kinematic, which merges saved pose graphs
(slam_toolbox/add_submap, slam_toolbox/merge_submaps; docs/slam.md).
    zros launch slam_toolbox merge_maps_kinematic_launch.py
"""
from zros.launch import LaunchDescription
from zros.launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        Node(package='slam_toolbox', executable='merge_maps_kinematic', name='slam_toolbox', output='screen'),
    ])
