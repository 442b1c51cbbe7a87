"""Two turtlesims and a mimic, as in the ROS 2 launch tutorial (the twin of
turtlesim_mimic.launch.yaml):
    zros launch configs/turtlesim_mimic.launch.py
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('port', default_value='8080', description='Port of the web view'),
        Node(package='turtlesim', executable='turtlesim_node', name='sim', namespace='turtlesim1', output='screen'),
        Node(package='turtlesim', executable='turtlesim_node', name='sim', namespace='turtlesim2', output='screen'),
        Node(package='turtlesim', executable='mimic', name='mimic', output='screen',
             remappings=[('/input/pose', '/turtlesim1/turtle1/pose'),
                         ('/output/cmd_vel', '/turtlesim2/turtle1/cmd_vel')]),
        Node(package='zros_view', executable='view', name='view', output='screen',
             parameters=[{'port': LaunchConfiguration('port'), 'topic': '/turtlesim1/sim/image'}]),
    ])
