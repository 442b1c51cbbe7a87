"""Parameters from a file and written inline (the twin of params_demo.launch.yaml):
    zros launch configs/params_demo.launch.py
    zros param get /param_talker published_text
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from zros.launch_ros.actions import Node
from zros.launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('text', default_value='Hello from params_demo.launch.yaml',
                              description='What the param_talker publishes'),
        Node(
            package='demo_nodes', executable='param_talker', name='param_talker', output='screen',
            parameters=[
                # A parameter file in the ROS 2 layout, passed on as --params-file.
                PathJoinSubstitution([FindPackageShare('configs'), 'params', 'talker.yaml']),
                # Later entries win, so this overrides the file's published_text; nested
                # dicts make dotted names (limits.max_rate, limits.enabled).
                {'published_text': LaunchConfiguration('text'),
                 'limits': {'max_rate': 10.0, 'enabled': True}},
            ]),
    ])
