"""turtlesim and its web view (the twin of turtlesim.launch.yaml):
    zros launch configs/turtlesim.launch.py port:=9000 background_r:=150
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('port', default_value='8080',
                              description='Port of the web view (the next free one up to +9 is taken if it is busy)'),
        DeclareLaunchArgument('background_r', default_value='69', description='Red channel of the background'),
        DeclareLaunchArgument('background_g', default_value='86', description='Green channel of the background'),
        DeclareLaunchArgument('background_b', default_value='255', description='Blue channel of the background'),
        Node(package='turtlesim', executable='turtlesim_node', name='turtlesim', output='screen',
             parameters=[{channel: LaunchConfiguration(channel)
                          for channel in ('background_r', 'background_g', 'background_b')}]),
        Node(package='zros_view', executable='view', name='view', output='screen',
             parameters=[{'port': LaunchConfiguration('port'), 'topic': '/turtlesim/image'}]),
    ])
