"""robot_state_publisher on the TurtleBot3's URDF, as turtlebot3_gazebo's launch file of that name.

    zros launch turtlebot3_gazebo robot_state_publisher.launch.py use_sim_time:=true

The URDF is `urdf/turtlebot3_$TURTLEBOT3_MODEL.urdf` of this package (burger when the variable is
unset); arguments are upstream's (Humble): `use_sim_time` (false) and `frame_prefix` ('': the
frames are `/base_link`, ..., which tf2 reads as `base_link`). ROBOTIS's own launch files that
include this one by path work unchanged.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration, PythonExpression
from zros.launch_ros.actions import Node


def generate_launch_description():
    model = os.environ.get('TURTLEBOT3_MODEL', 'burger') or 'burger'
    urdf = os.path.join(get_package_share_directory('turtlebot3_gazebo'), 'urdf', f'turtlebot3_{model}.urdf')
    with open(urdf) as file:
        robot_description = file.read()
    frame_prefix = LaunchConfiguration('frame_prefix', default='')
    return LaunchDescription([
        DeclareLaunchArgument('use_sim_time', default_value='false',
                              description='Follow /clock (the simulator) instead of the wall clock'),
        Node(package='robot_state_publisher', executable='robot_state_publisher', name='robot_state_publisher',
             output='screen',
             parameters=[{'use_sim_time': LaunchConfiguration('use_sim_time'),
                          'robot_description': robot_description,
                          'frame_prefix': PythonExpression(["'", frame_prefix, "/'"])}]),
    ])
