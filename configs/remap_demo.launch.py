"""The talker and listener over /news instead of /chatter, the listener renamed (the twin of
remap_demo.launch.yaml):
    zros launch configs/remap_demo.launch.py
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    topic = LaunchConfiguration('topic')
    return LaunchDescription([
        DeclareLaunchArgument('topic', default_value='/news', description='Where the chatter goes'),
        Node(package='demo_nodes', executable='talker', name='talker', output='screen',
             remappings=[('chatter', topic)]),
        Node(package='demo_nodes', executable='listener', name='news_reader', output='screen',
             remappings=[('chatter', topic)]),
    ])
