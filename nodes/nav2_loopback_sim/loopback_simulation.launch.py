"""The loopback simulator with Nav2's parameter file, as nav2_loopback_sim's launch file:
    zros launch nav2_loopback_sim loopback_simulation.launch.py
    zros launch nav2_loopback_sim loopback_simulation.launch.py params_file:=my_params.yaml scan_frame_id:=rplidar_link
It sits in the package folder itself, not in launch/, because that is where ROS installs it and
where nav2_bringup's tb3_loopback_simulation.launch.py includes it from.
`params_file` (nav2_bringup's nav2_params.yaml) gives its `loopback_simulator:` section;
`scan_frame_id` (base_scan: TurtleBot3's lidar) overrides the file's.
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    default_params = os.path.join(get_package_share_directory('nav2_bringup'), 'params', 'nav2_params.yaml')
    return LaunchDescription([
        DeclareLaunchArgument('scan_frame_id', default_value='base_scan',
                              description='The frame the simulated scan is published in'),
        DeclareLaunchArgument('params_file', default_value=default_params,
                              description='Full path to the ROS2 parameters file to use for all launched nodes'),
        Node(package='nav2_loopback_sim', executable='loopback_simulator', name='loopback_simulator',
             output='screen',
             parameters=[LaunchConfiguration('params_file'), {'scan_frame_id': LaunchConfiguration('scan_frame_id')}]),
    ])
