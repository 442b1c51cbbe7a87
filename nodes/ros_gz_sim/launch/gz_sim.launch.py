"""ros_gz_sim's gz_sim.launch.py: Gazebo Sim (`gz sim GZ_ARGS`), played by zros's simulator.
    zros launch ros_gz_sim gz_sim.launch.py gz_args:='-r -s /path/to/world.sdf'
    zros launch ros_gz_sim gz_sim.launch.py gz_args:='-r empty.sdf' on_exit_shutdown:=true
The arguments are ros_gz_sim's: `gz_args` (the `gz sim` command line: world file, `-r`, `-s`,
`-g`, `-v N`, ...), `gz_version` (8, Harmonic), `on_exit_shutdown`; the deprecated `ign_args`
is used when `gz_args` is empty; `ign_version` and `debugger` have no counterpart. Model folders
of every package zros knows are on the model path already (what upstream adds to
GZ_SIM_RESOURCE_PATH from the packages' exports). See docs/robot.md, "Gazebo Sim (ros_gz)".
"""
import shlex

from zros.launch import LaunchDescription
from zros.launch.actions import DeclareLaunchArgument, OpaqueFunction, Shutdown
from zros.launch.substitutions import LaunchConfiguration
from zros.launch_ros.actions import Node

#: ros_gz_sim's gz_sim.launch.py arguments (Jazzy, Harmonic) and their defaults.
DEFAULTS = {'gz_args': '', 'gz_version': '8', 'ign_args': '', 'ign_version': '', 'debugger': 'false',
            'on_exit_shutdown': 'false'}
HELP = {
    'gz_args': 'Arguments to gz sim: the world file, -r (run), -s (server only), -g (GUI only), -v N',
    'gz_version': "Gazebo Sim's major version (zros plays Harmonic's behaviour for any)",
    'ign_args': 'Deprecated: gz_args', 'ign_version': 'Deprecated: gz_version',
    'debugger': 'Run in a debugger (not in zros)', 'on_exit_shutdown': 'Shut the whole launch down when gz sim exits',
}


def _gz_sim(context):
    arguments = {name: LaunchConfiguration(name).perform(context) for name in DEFAULTS}
    command = arguments['gz_args'] or arguments['ign_args']
    on_exit = Shutdown() if arguments['on_exit_shutdown'].lower() == 'true' else None
    return [Node(package='ros_gz_sim', executable='gz', name='gazebo', output='screen',
                 arguments=['sim', *shlex.split(command)], on_exit=on_exit)]


def generate_launch_description():
    declared = [DeclareLaunchArgument(name, default_value=value, description=HELP[name])
                for name, value in DEFAULTS.items()]
    return LaunchDescription([*declared, OpaqueFunction(function=_gz_sim)])
