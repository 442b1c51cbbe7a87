"""namespaced.launch.py twice, each with its own `robot` argument, inside a `fleet` namespace
group (the twin of multi_robot.launch.yaml):
    zros launch configs/multi_robot.launch.py --print
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, GroupAction, IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration, ThisLaunchFileDir
from zros.launch_ros.actions import PushRosNamespace


def generate_launch_description():
    fleet = LaunchConfiguration('fleet')
    return LaunchDescription([
        DeclareLaunchArgument('fleet', default_value='fleet', description='Namespace that holds every robot'),
        GroupAction([
            PushRosNamespace(fleet),
            IncludeLaunchDescription(
                PythonLaunchDescriptionSource([ThisLaunchFileDir(), '/namespaced.launch.py']),
                launch_arguments={'robot': 'robot1'}.items()),
        ]),
        GroupAction([
            PushRosNamespace(fleet),
            IncludeLaunchDescription(
                PythonLaunchDescriptionSource(
                    os.path.join(get_package_share_directory('zros'), 'configs', 'namespaced.launch.py')),
                launch_arguments={'robot': 'robot2'}.items()),
        ]),
    ])
