"""turtlebot3_cartographer's occupancy_grid.launch.py: cartographer_ros's occupancy grid node,
publishing /map every publish_period_sec at `resolution` (the .yaml twin says the same)."""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('resolution', default_value='0.05',
                              description='Resolution of a grid cell in the published occupancy grid'),
        DeclareLaunchArgument('publish_period_sec', default_value='1.0', description='OccupancyGrid publishing period'),
        DeclareLaunchArgument('use_sim_time', default_value='false', description='Use simulation (Gazebo) clock if true'),
        Node(package='cartographer_ros', executable='cartographer_occupancy_grid_node',
             name='cartographer_occupancy_grid_node', output='screen',
             parameters=[{'use_sim_time': LaunchConfiguration('use_sim_time')}],
             arguments=['-resolution', LaunchConfiguration('resolution'),
                        '-publish_period_sec', LaunchConfiguration('publish_period_sec')]),
    ])
