"""slam_toolbox's online sync launch file: zros has one SLAM node, so this is
online_async_launch.py with the sync parameter file (docs/slam.md).
    zros launch slam_toolbox online_sync_launch.py use_sim_time:=True
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration, PathJoinSubstitution, ThisLaunchFileDir
from zros.launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='true', description='Use simulation/Gazebo clock'),
        DeclareLaunchArgument('slam_params_file',
                              default_value=PathJoinSubstitution([FindPackageShare('slam_toolbox'), 'config',
                                                                  'mapper_params_online_sync.yaml']),
                              description='Full path to the ROS 2 parameters file to use for the slam_toolbox node'),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(PathJoinSubstitution([ThisLaunchFileDir(), 'online_async_launch.py'])),
            launch_arguments={'use_sim_time': LaunchConfiguration('use_sim_time'),
                              'slam_params_file': LaunchConfiguration('slam_params_file')}.items()),
    ])
