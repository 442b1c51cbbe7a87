"""The talker and the listener, as ROS 2's demo_nodes_cpp talker_listener launch file:
    zros launch demo_nodes talker_listener.launch.py
    zros launch demo_nodes talker_listener.launch.py text:='Hi there' --print
The talker takes its parameters from this package's param/talker.yaml (found through the
package's share directory, as a ROS 2 package installs it), the text from a launch argument,
kept a string whatever it looks like (ParameterValue with value_type=str: `text:=42` is '42').
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node
from zros.launch_ros.parameter_descriptions import ParameterValue


def generate_launch_description():
    params = os.path.join(get_package_share_directory('demo_nodes'), 'param', 'talker.yaml')
    return LaunchDescription([
        DeclareLaunchArgument('text', default_value='Hello World', description='What the talker publishes'),
        Node(package='demo_nodes', executable='param_talker', name='talker', output='screen',
             parameters=[params, {'published_text': ParameterValue(LaunchConfiguration('text'), value_type=str)}]),
        Node(package='demo_nodes', executable='listener', output='screen'),
    ])
