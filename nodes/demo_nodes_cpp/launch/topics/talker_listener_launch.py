"""demo_nodes_cpp's talker and listener (the twin of talker_listener_launch.xml), written with
ROS 2's module names as the ROS package writes it:
    zros launch nodes/demo_nodes_cpp/launch/topics/talker_listener_launch.py
"""
from launch import LaunchDescription
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        Node(package='demo_nodes_cpp', executable='talker', output='screen'),
        Node(package='demo_nodes_cpp', executable='listener', output='screen'),
    ])
