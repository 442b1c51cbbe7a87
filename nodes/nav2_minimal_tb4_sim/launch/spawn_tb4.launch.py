"""nav2_minimal_tb4_sim's spawn_tb4.launch.py: the TurtleBot4 into a running Gazebo Sim world.
    zros launch ros_gz_sim gz_sim.launch.py gz_args:="-r -s depot.sdf"     # first, the world
    zros launch nav2_minimal_tb4_sim spawn_tb4.launch.py x_pose:=-8.0 y_pose:=0.0
Nav2 Jazzy's tb4_simulation_launch.py includes it, next to a robot_state_publisher of
nav2_minimal_tb4_description's turtlebot4.urdf.xacro: the robot is spawned from that node's
`robot_description` topic, as upstream's is. The same arguments as upstream: `namespace`,
`robot_name` (turtlebot4), `use_simulator` (spawn only if true), `use_sim_time`, and the pose
`x_pose`, `y_pose`, `z_pose`, `roll`, `pitch`, `yaw` (-8.0, -0.5, 0.01, 0, 0, 0). It starts
ros_gz_bridge's parameter_bridge on configs/tb4_bridge.yaml and ros_gz_sim's `create`; the
camera image bridges of the real file have no counterpart (zros renders no images). See
docs/robot.md, "TurtleBot4 (Nav2 Jazzy)".
"""
import os

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument
from zros.launch.conditions import IfCondition
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    share = get_package_share_directory('nav2_minimal_tb4_sim')
    namespace = LaunchConfiguration('namespace')
    use_sim_time = LaunchConfiguration('use_sim_time')
    pose = [LaunchConfiguration(name, default=default) for name, default in
            (('x_pose', '-8.00'), ('y_pose', '-0.50'), ('z_pose', '0.01'),
             ('roll', '0.00'), ('pitch', '0.00'), ('yaw', '0.00'))]
    pose_flags = [item for flag, value in zip(('-x', '-y', '-z', '-R', '-P', '-Y'), pose) for item in (flag, value)]
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace'),
        DeclareLaunchArgument('robot_name', default_value='turtlebot4', description='name of the robot'),
        DeclareLaunchArgument('use_simulator', default_value='True', description='Whether to start the simulator'),
        DeclareLaunchArgument('use_sim_time', default_value='true',
                              description='Use simulation (Gazebo) clock if true'),
        Node(package='ros_gz_bridge', executable='parameter_bridge', name='bridge_ros_gz', namespace=namespace,
             output='screen',
             parameters=[{'config_file': os.path.join(share, 'configs', 'tb4_bridge.yaml'),
                          'use_sim_time': use_sim_time}]),
        Node(package='ros_gz_sim', executable='create', namespace=namespace, output='screen',
             condition=IfCondition(LaunchConfiguration('use_simulator')),
             arguments=['-name', LaunchConfiguration('robot_name'), '-topic', 'robot_description', *pose_flags],
             parameters=[{'use_sim_time': use_sim_time}]),
    ])
