"""nav2_minimal_tb3_sim's spawn_tb3.launch.py: the TurtleBot3 waffle into a running Gazebo Sim world.
    zros launch ros_gz_sim gz_sim.launch.py gz_args:="-r -s $WORLD"      # first, the world
    zros launch nav2_minimal_tb3_sim spawn_tb3.launch.py x_pose:=-2.0 y_pose:=-0.5
Nav2 Jazzy's tb3_simulation_launch.py includes it. The same arguments as upstream: `namespace`,
`robot_name` (turtlebot3_waffle), `robot_sdf` (urdf/gz_waffle.sdf.xacro, run through xacro with
`namespace:=`), and the pose `x_pose`, `y_pose`, `z_pose`, `roll`, `pitch`, `yaw` (-2.0, -0.5,
0.01, 0, 0, 0). It starts ros_gz_bridge's parameter_bridge on configs/turtlebot3_waffle_bridge.yaml
(the robot's topics and /clock become ROS topics) and ros_gz_sim's `create`, and puts this
package's models/ on GZ_SIM_RESOURCE_PATH. See docs/robot.md, "Gazebo Sim (ros_gz)".
"""
import os
from pathlib import Path

from zros.ament_index_python.packages import get_package_share_directory
from zros.launch import LaunchDescription
from zros.launch.actions import AppendEnvironmentVariable, DeclareLaunchArgument
from zros.launch.substitutions import Command, FindExecutable, LaunchConfiguration
from zros.launch_ros.actions import Node


def generate_launch_description():
    share = get_package_share_directory('nav2_minimal_tb3_sim')
    namespace = LaunchConfiguration('namespace')
    pose = [LaunchConfiguration(name, default=default) for name, default in
            (('x_pose', '-2.00'), ('y_pose', '-0.50'), ('z_pose', '0.01'),
             ('roll', '0.00'), ('pitch', '0.00'), ('yaw', '0.00'))]
    robot_description = Command([FindExecutable(name='xacro'), ' namespace:=', namespace, ' ',
                                 LaunchConfiguration('robot_sdf')])
    pose_flags = [item for flag, value in zip(('-x', '-y', '-z', '-R', '-P', '-Y'), pose) for item in (flag, value)]
    return LaunchDescription([
        DeclareLaunchArgument('namespace', default_value='', description='Top-level namespace'),
        DeclareLaunchArgument('robot_name', default_value='turtlebot3_waffle', description='name of the robot'),
        DeclareLaunchArgument('robot_sdf', default_value=os.path.join(share, 'urdf', 'gz_waffle.sdf.xacro'),
                              description='Full path to robot sdf file to spawn the robot in gazebo'),
        AppendEnvironmentVariable('GZ_SIM_RESOURCE_PATH', os.path.join(share, 'models')),
        AppendEnvironmentVariable('GZ_SIM_RESOURCE_PATH', str(Path(share).parent.resolve())),
        Node(package='ros_gz_bridge', executable='parameter_bridge', namespace=namespace, output='screen',
             parameters=[{'config_file': os.path.join(share, 'configs', 'turtlebot3_waffle_bridge.yaml'),
                          'expand_gz_topic_names': True, 'use_sim_time': True}]),
        Node(package='ros_gz_sim', executable='create', namespace=namespace, output='screen',
             arguments=['-name', LaunchConfiguration('robot_name'), '-string', robot_description, *pose_flags]),
    ])
