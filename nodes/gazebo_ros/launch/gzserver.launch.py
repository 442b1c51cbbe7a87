"""gazebo_ros's gzserver.launch.py: the simulator (zros's 2D world) on a Gazebo world file.
    zros launch gazebo_ros gzserver.launch.py world:=/path/to/my.world pause:=true
Gazebo's arguments are all accepted; `world`, `pause`, `seed`, `verbose`, `params_file`,
`extra_gazebo_args` and `server_required` take effect, the rest (physics engine, recording,
gdb, ...) have no counterpart in zros. See docs/robot.md, "gazebo_ros".
"""
import shlex

from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, OpaqueFunction, Shutdown
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node

#: (name, default, description): Gazebo's gzserver.launch.py arguments.
ARGUMENTS = (
    ('world', '', 'World file (.world/.sdf, or a zros .yaml world); empty: an empty world'),
    ('params_file', '', 'Parameter file for the gazebo node'),
    ('version', 'false', "Gazebo's version (nothing in zros)"),
    ('verbose', 'false', 'More log output'),
    ('lockstep', 'false', 'Sensors in lockstep with physics (always, in zros)'),
    ('help', 'false', "gzserver's help (nothing in zros)"),
    ('pause', 'false', 'Start with physics paused'),
    ('physics', '', 'Physics engine (zros has one)'),
    ('play', '', 'Log file to play back (not in zros)'),
    ('record', 'false', 'Record state data (not in zros; use zros bag record)'),
    ('record_encoding', '', 'Not in zros'),
    ('record_path', '', 'Not in zros'),
    ('record_period', '', 'Not in zros'),
    ('record_filter', '', 'Not in zros'),
    ('seed', '', 'Random seed of every noise generator'),
    ('iters', '', 'Number of iterations (not in zros)'),
    ('minimal_comms', 'false', 'Not in zros'),
    ('profile', '', 'Physics preset profile (not in zros)'),
    ('extra_gazebo_args', '', "More gzserver options (gazebo_ros gzserver's command line)"),
    ('gdb', 'false', 'Not in zros'),
    ('valgrind', 'false', 'Not in zros'),
    ('init', 'true', 'libgazebo_ros_init.so: /reset_simulation, /pause_physics, ... (always in zros)'),
    ('factory', 'true', 'libgazebo_ros_factory.so: /spawn_entity, /delete_entity (always in zros)'),
    ('force_system', 'true', 'Load the system plugins (always in zros)'),
    ('server_required', 'false', 'Shut the whole launch down when the server exits'),
)


def _server(context):
    def value(name):
        return LaunchConfiguration(name).perform(context)
    arguments = [value('world')] if value('world') else []
    if value('pause').lower() == 'true':
        arguments.append('-u')
    if value('verbose').lower() == 'true':
        arguments.append('--verbose')
    if value('seed'):
        arguments += ['--seed', value('seed')]
    arguments += shlex.split(value('extra_gazebo_args'))
    return [Node(package='gazebo_ros', executable='gzserver', name='gazebo', output='screen', arguments=arguments,
                 parameters=[value('params_file')] if value('params_file') else [],
                 on_exit=Shutdown() if value('server_required').lower() == 'true' else None)]


def generate_launch_description():
    return LaunchDescription([
        *(DeclareLaunchArgument(name, default_value=default, description=description)
          for name, default, description in ARGUMENTS),
        OpaqueFunction(function=_server),
    ])
