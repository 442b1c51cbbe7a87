"""The laptop's half of a two-machine TurtleBot3: localization (map_server + AMCL, or SLAM with
`slam:=True`), Nav2's servers and, with `view:=true`, the view; everything that needs CPU and a
screen, none of what needs the robot's hardware. It is turtlebot3_navigation2's
navigation2.launch.py with the defaults of a robot elsewhere: simulated time from the robot's
/clock, and the view off unless asked (on Wi-Fi it costs a map and a scan stream more).
    zros router &                                   # the laptop holds the router
    zros launch turtlebot3_bringup laptop.launch.py                 # map + AMCL
    zros launch turtlebot3_bringup laptop.launch.py slam:=True view:=true
    zros run turtlebot3_teleop teleop_keyboard                       # teleop, from the laptop too
The robot runs robot.launch.py; docs/multi-machine.md ("A robot on Wi-Fi") sets both up.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from zros.launch.launch_description_sources import PythonLaunchDescriptionSource
from zros.launch.substitutions import LaunchConfiguration


def generate_launch_description():
    navigation = os.path.join(get_package_share_directory('turtlebot3_navigation2'), 'launch',
                              'navigation2.launch.py')
    share = get_package_share_directory('turtlebot3_navigation2')
    return LaunchDescription([
        DeclareLaunchArgument('map', default_value=os.path.join(share, 'map', 'map.yaml'),
                              description='The map AMCL localizes in (unused with slam:=True)'),
        DeclareLaunchArgument('slam', default_value='False', description='Build the map (SLAM) instead of AMCL'),
        DeclareLaunchArgument('use_sim_time', default_value='true', description="Follow the robot's /clock"),
        DeclareLaunchArgument('view', default_value='false', description='Also start the view (rviz2)'),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource(navigation),
            launch_arguments={'map': LaunchConfiguration('map'), 'slam': LaunchConfiguration('slam'),
                              'use_sim_time': LaunchConfiguration('use_sim_time'),
                              'rviz': LaunchConfiguration('view')}.items()),
    ])
