"""turtlebot3_cartographer's cartographer.launch.py, in the shape of ROBOTIS's: cartographer_ros's
cartographer_node with the Lua configuration, occupancy_grid.launch.py for /map, and rviz2.
    zros launch turtlebot3_cartographer cartographer.launch.py use_sim_time:=True
cartographer_ros's nodes run zros's SLAM (docs/slam.md); the .yaml twin says the same.
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.conditions import IfCondition
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration, PathJoinSubstitution, ThisLaunchFileDir
from zros.launch_ros.actions import Node
from zros.launch_ros.substitutions import FindPackageShare


def generate_launch_description():
    use_sim_time = LaunchConfiguration('use_sim_time')
    return LaunchDescription([
        DeclareLaunchArgument('cartographer_config_dir',
                              default_value=PathJoinSubstitution([FindPackageShare('turtlebot3_cartographer'), 'config']),
                              description='Full path to config file to load'),
        DeclareLaunchArgument('configuration_basename', default_value='turtlebot3_lds_2d.lua',
                              description='Name of lua file for cartographer'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        DeclareLaunchArgument('resolution', default_value='0.05',
                              description='Resolution of a grid cell in the published occupancy grid'),
        DeclareLaunchArgument('publish_period_sec', default_value='1.0', description='OccupancyGrid publishing period'),
        DeclareLaunchArgument('use_rviz', default_value='true', description='Also open the scene view (rviz2)'),
        Node(package='cartographer_ros', executable='cartographer_node', name='cartographer_node', output='screen',
             parameters=[{'use_sim_time': use_sim_time}],
             arguments=['-configuration_directory', LaunchConfiguration('cartographer_config_dir'),
                        '-configuration_basename', LaunchConfiguration('configuration_basename')]),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource([ThisLaunchFileDir(), '/occupancy_grid.launch.py']),
            launch_arguments={'use_sim_time': use_sim_time, 'resolution': LaunchConfiguration('resolution'),
                              'publish_period_sec': LaunchConfiguration('publish_period_sec')}.items()),
        Node(package='rviz2', executable='rviz2', name='rviz2', output='screen',
             arguments=['-d', PathJoinSubstitution([FindPackageShare('turtlebot3_cartographer'), 'rviz',
                                                    'tb3_cartographer.rviz'])],
             parameters=[{'use_sim_time': use_sim_time}], condition=IfCondition(LaunchConfiguration('use_rviz'))),
    ])
