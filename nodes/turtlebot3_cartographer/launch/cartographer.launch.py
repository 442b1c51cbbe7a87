"""turtlebot3_cartographer's cartographer.launch.py: zros's SLAM node in Cartographer's place
(one SLAM implementation, docs/slam.md), publishing /map every publish_period_sec.
    zros launch turtlebot3_cartographer cartographer.launch.py use_sim_time:=True
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.conditions import IfCondition
from zros.launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from zros.launch_ros.actions import Node
from zros.launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    use_sim_time = LaunchConfiguration('use_sim_time')
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('resolution', default_value='0.05', description='Resolution of a grid cell in the published occupancy grid'),
        DeclareLaunchArgument('publish_period_sec', default_value='1.0', description='OccupancyGrid publishing period'),
        DeclareLaunchArgument('use_rviz', default_value='true', description='Also open the scene view (rviz2)'),
        DeclareLaunchArgument('configuration_directory',
                              default_value=PathJoinSubstitution([FindPackageShare('turtlebot3_cartographer'), 'config']),
                              description='Full path to config file to load'),
        DeclareLaunchArgument('configuration_basename', default_value='turtlebot3_lds_2d.yaml',
                              description='Name of the parameter file in configuration_directory'),
        Node(package='slam_toolbox', executable='async_slam_toolbox_node', name='cartographer_node', output='screen',
             parameters=[PathJoinSubstitution([LaunchConfiguration('configuration_directory'),
                                               LaunchConfiguration('configuration_basename')]),
                         {'use_sim_time': use_sim_time, 'resolution': LaunchConfiguration('resolution'),
                          'map_update_interval': LaunchConfiguration('publish_period_sec')}]),
        Node(package='rviz2', executable='rviz2', name='rviz2', output='screen',
             parameters=[{'use_sim_time': use_sim_time}], condition=IfCondition(LaunchConfiguration('use_rviz'))),
    ])
