"""The talker/listener demo as a Python launch file (the twin of talker_listener.launch.yaml):
    zros launch configs/talker_listener.launch.py
    zros launch configs/talker_listener.launch.py topic:=news --print
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    topic = LaunchConfiguration('topic')
    return LaunchDescription([
        DeclareLaunchArgument('topic', default_value='chatter',
                              description='Topic the talker publishes and the listener subscribes to'),
        Node(package='demo_nodes', executable='talker', output='screen', remappings=[('chatter', topic)]),
        Node(package='demo_nodes', executable='listener', output='screen', remappings=[('chatter', topic)]),
    ])
