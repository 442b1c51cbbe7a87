"""gazebo_ros's gzclient.launch.py: Gazebo's window, played by zros's browser view.
    zros launch gazebo_ros gzclient.launch.py
Starts zros_view's view (fixed frame `odom`, simulated time), as turtlebot3_gazebo's
`view:=true` does, unless a view already serves on its usual port (8080): then nothing, so a
launch file that includes gzclient next to a running `zros view` opens no second one. Gazebo's
arguments (gdb, valgrind, version, verbose, gui_required) are accepted; `gui_required` shuts
the launch down when the view exits. See docs/robot.md, "gazebo_ros".
"""
import socket

from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, LogInfo, OpaqueFunction, Shutdown
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node

VIEW_PORT = 8080   # zros_view's default port

ARGUMENTS = (
    ('version', 'false', "Gazebo's version (nothing in zros)"),
    ('verbose', 'false', 'More log output'),
    ('gdb', 'false', 'Not in zros'),
    ('valgrind', 'false', 'Not in zros'),
    ('gui_required', 'false', 'Shut the whole launch down when the view exits'),
)


def _view_running():
    try:
        with socket.create_connection(('127.0.0.1', VIEW_PORT), timeout=0.5):
            return True
    except OSError:
        return False


def _client(context):
    if _view_running():
        return [LogInfo(msg=f'gzclient: a view already serves http://127.0.0.1:{VIEW_PORT}; not starting another')]
    required = LaunchConfiguration('gui_required').perform(context).lower() == 'true'
    return [Node(package='zros_view', executable='view', name='gzclient', output='screen',
                 parameters=[{'use_sim_time': True, 'fixed_frame': 'odom'}],
                 on_exit=Shutdown() if required else None)]


def generate_launch_description():
    return LaunchDescription([
        *(DeclareLaunchArgument(name, default_value=default, description=description)
          for name, default, description in ARGUMENTS),
        OpaqueFunction(function=_client),
    ])
