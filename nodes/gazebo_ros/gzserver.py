"""gzserver: Gazebo's server command line, played by zros's simulator (turtlebot3_gazebo gzserver).

    gzserver -s libgazebo_ros_init.so -s libgazebo_ros_factory.so my.world     # Nav2's form
    zros run gazebo_ros gzserver --verbose -u worlds/turtlebot3_world.world
    zros launch gazebo_ros gzserver.launch.py world:=my.world                  # the usual way

It takes Gazebo classic's options, so launch files that start `gzserver` as a process (Nav2's
tb3_simulation_launch.py) or through gazebo_ros's launch files run unchanged: the world file
(an SDF `.world`, or a zros YAML world), `-u`/`--pause` (start paused), `--seed N`; the `-s`
system plugins (libgazebo_ros_init.so, _factory.so, _state.so) are what zros's simulator always
serves (/reset_simulation, /spawn_entity, /get_entity_state, ...), so they are accepted and
have no further effect. Other Gazebo options are accepted and ignored with one warning.

Unlike turtlebot3_gazebo's gzserver, no robot is there at the start: robots come in through
/spawn_entity (gazebo_ros's spawn_entity.py), as in Gazebo. The node is `/gazebo`, as Gazebo's.
"""
from __future__ import annotations

import argparse
import sys

import zros
from zros.arguments import NodeArgumentParser, remove_ros_args
from zros.executors import ExternalShutdownException, spin_nodes
from zros.parameter import Parameter

from nodes.turtlebot3_gazebo.gzserver import GazeboNode

__all__ = ['main', 'entry_point', 'gazebo_parameters']

#: Gazebo classic's options that take a value and that zros does not model.
_IGNORED_WITH_VALUE = ('-e', '--physics', '--iters', '-p', '--play', '--record_path', '--record_period',
                       '--record_filter', '--record_encoding', '--profile', '-o')
_IGNORED_FLAGS = ('-r', '--record', '--lockstep', '--minimal_comms', '-q', '--quiet', '--pause_on_start')


def _parser() -> argparse.ArgumentParser:
    parser = NodeArgumentParser(prog='gzserver', description="Gazebo's server, played by zros's 2D simulator")
    parser.add_argument('world', nargs='?', default='', help='world file (.world/.sdf, or a zros .yaml world)')
    parser.add_argument('-s', '--server-plugin', action='append', default=[], help='system plugin (accepted)')
    parser.add_argument('-u', '--pause', action='store_true', help='start with physics paused')
    parser.add_argument('--seed', type=int, help='random seed')
    parser.add_argument('--verbose', action='store_true', help='log more (accepted)')
    for option in _IGNORED_WITH_VALUE:
        parser.add_argument(option, dest=f'ignored{option}', metavar='VALUE', help=argparse.SUPPRESS)
    for flag in _IGNORED_FLAGS:
        parser.add_argument(flag, dest=f'ignored{flag}', action='store_true', help=argparse.SUPPRESS)
    return parser


def gazebo_parameters(argv: list[str]) -> tuple[list[Parameter], list[str]]:
    """The simulator's parameters for Gazebo's command line `argv` (without the program name),
    and the options given that zros ignores. CliError (one line) for a bad command line."""
    args = _parser().parse_args(argv)
    ignored = [name.removeprefix('ignored') for name, value in vars(args).items()
               if name.startswith('ignored') and value not in (None, False)]
    parameters = [Parameter('spawn_robot', value=False)]
    if args.world:
        parameters.append(Parameter('world', value=args.world))
    if args.pause:
        parameters.append(Parameter('paused', value=True))
    if args.seed is not None:
        parameters.append(Parameter('seed', value=args.seed))
    return parameters, ignored


def main(args: list[str] | None = None) -> None:
    argv = list(sys.argv if args is None else args)
    parameters, ignored = gazebo_parameters(remove_ros_args(argv)[1:])
    try:
        with zros.init(args=argv):
            node = GazeboNode(parameter_overrides=parameters)
            if ignored:
                node.get_logger().warn(f"gzserver: ignoring Gazebo options zros does not model: {', '.join(ignored)}")
            spin_nodes(node, num_threads=4)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


def entry_point() -> None:
    """The `gzserver` command (pyproject's console script): `zros run gazebo_ros gzserver ARGS`."""
    from zros.cli.main import entry_point as zros_entry_point
    zros_entry_point(['run', 'gazebo_ros', 'gzserver', *sys.argv[1:]])


if __name__ == '__main__':
    main(sys.argv)
