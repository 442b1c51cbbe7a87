"""One robot's talker and listener under a namespace given as an argument (the twin of
namespaced.launch.yaml):
    zros launch configs/namespaced.launch.py robot:=robot7
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, GroupAction
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node, PushRosNamespace


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('robot', default_value='robot1', description="Namespace of this robot's nodes"),
        GroupAction([
            PushRosNamespace(LaunchConfiguration('robot')),
            Node(package='demo_nodes', executable='talker', name='talker'),
            Node(package='demo_nodes', executable='listener', name='listener'),
        ]),
    ])
