"""turtlebot3_bighouse: the big house (zros.sim.worlds, docs/robot.md) with a TurtleBot3 in it, as
the courses' turtlebot3_bighouse.launch.py (the twin of turtlebot3_bighouse.launch.yaml).
    export TURTLEBOT3_MODEL=burger
    zros launch turtlebot3_gazebo turtlebot3_bighouse.launch.py
    zros launch turtlebot3_gazebo turtlebot3_bighouse.launch.py x_pose:=2.7 y_pose:=-1.1 view:=true
use_sim_time, real_time_factor, paused and view are robot_world.launch.py's arguments.
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration, ThisLaunchFileDir


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('x_pose', default_value='-2.0', description='Where the robot starts, in metres'),
        DeclareLaunchArgument('y_pose', default_value='-0.5', description='Where the robot starts, in metres'),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource([ThisLaunchFileDir(), '/robot_world.launch.py']),
            launch_arguments={'world': 'turtlebot3_bighouse', 'x_pose': LaunchConfiguration('x_pose'),
                              'y_pose': LaunchConfiguration('y_pose')}.items()),
    ])
