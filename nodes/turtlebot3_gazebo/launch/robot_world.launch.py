"""The simulated world with one TurtleBot3 in it, and robot_state_publisher on its URDF: what
turtlebot3_world, turtlebot3_house and empty_world include (the twin of robot_world.launch.yaml).
    zros launch turtlebot3_gazebo robot_world.launch.py world:=/path/to/my_world.yaml
The robot model comes from TURTLEBOT3_MODEL (burger when unset), as in turtlebot3_gazebo, whose
robot_state_publisher.launch.py reads the same URDF file. See docs/robot.md.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.conditions import IfCondition
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node

#: The arguments every world launch file passes on, with robot_world's defaults and descriptions.
ARGUMENTS = (
    ('x_pose', '0.0', 'Where the robot starts, in metres'),
    ('y_pose', '0.0', 'Where the robot starts, in metres'),
    ('use_sim_time', 'true', "Whether the robot's own nodes follow /clock"),
    ('real_time_factor', '1.0', 'Simulated seconds per wall second (0: as fast as possible)'),
    ('paused', 'false', 'Start with physics paused'),
    ('view', 'false', "Also start the browser view (zros_view), Gazebo client's role"),
)


def generate_launch_description():
    model = os.environ.get('TURTLEBOT3_MODEL', 'burger')
    urdf = os.path.join(get_package_share_directory('turtlebot3_description'), 'urdf', f'turtlebot3_{model}.urdf')
    with open(urdf) as file:
        robot_description = file.read()
    use_sim_time = LaunchConfiguration('use_sim_time')
    return LaunchDescription([
        DeclareLaunchArgument(
            'world', description='A shipped world (empty_world, turtlebot3_world, turtlebot3_house) or a world file'),
        *(DeclareLaunchArgument(name, default_value=default, description=description)
          for name, default, description in ARGUMENTS),
        Node(package='turtlebot3_gazebo', executable='gzserver', name='gazebo', output='screen',
             parameters=[{name: LaunchConfiguration(name)
                          for name in ('world', 'x_pose', 'y_pose', 'real_time_factor', 'paused')},
                         {'publish_robot_frames': False}]),   # robot_state_publisher's job, from the URDF
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='robot_state_publisher',
             output='screen', parameters=[{'use_sim_time': use_sim_time, 'robot_description': robot_description}]),
        Node(package='zros_view', executable='view', name='view', output='screen',
             condition=IfCondition(LaunchConfiguration('view')),
             parameters=[{'use_sim_time': use_sim_time}]),   # fixed frame: odom, then map once SLAM or AMCL has it
    ])
