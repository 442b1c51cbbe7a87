"""slam_toolbox's localization launch file: zros's SLAM localizing in a saved pose graph
(docs/slam.md, "Localizing in a saved map").
    zros launch slam_toolbox localization_launch.py slam_params_file:=my_localization.yaml
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from zros.launch_ros.actions import Node
from zros.launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='true', description='Use simulation/Gazebo clock'),
        DeclareLaunchArgument('slam_params_file',
                              default_value=PathJoinSubstitution([FindPackageShare('slam_toolbox'), 'config',
                                                                  'mapper_params_localization.yaml']),
                              description='Full path to the ROS 2 parameters file to use for the slam_toolbox node'),
        Node(package='slam_toolbox', executable='localization_slam_toolbox_node', name='slam_toolbox',
             output='screen', parameters=[LaunchConfiguration('slam_params_file'),
                                          {'use_sim_time': LaunchConfiguration('use_sim_time')}]),
    ])
