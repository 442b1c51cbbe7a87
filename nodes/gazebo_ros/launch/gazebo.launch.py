"""gazebo_ros's gazebo.launch.py: gzserver.launch.py and gzclient.launch.py together.
    zros launch gazebo_ros gazebo.launch.py world:=/path/to/my.world gui:=false
`server` and `gui` (both true) choose which half runs; every other argument goes to the
included files (see them, and docs/robot.md, "gazebo_ros").
"""
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.conditions import IfCondition
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration, ThisLaunchFileDir


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('gui', default_value='true', description='Start the view (gzclient)'),
        DeclareLaunchArgument('server', default_value='true', description='Start the simulator (gzserver)'),
        IncludeLaunchDescription(PythonLaunchDescriptionSource([ThisLaunchFileDir(), '/gzserver.launch.py']),
                                 condition=IfCondition(LaunchConfiguration('server'))),
        IncludeLaunchDescription(PythonLaunchDescriptionSource([ThisLaunchFileDir(), '/gzclient.launch.py']),
                                 condition=IfCondition(LaunchConfiguration('gui'))),
    ])
