"""gz: Gazebo Sim's command line (`gz sim`), played by zros's simulator in Gazebo Sim's shape.

    gz sim -r -s /tmp/nav2_world.sdf             # Nav2 Jazzy's tb3_simulation_launch.py: server, running
    zros launch ros_gz_sim gz_sim.launch.py gz_args:='-r -s my_world.sdf'
    gz sim -g                                    # the GUI only: zros's browser view

`gz sim` runs the world file (an SDF world as Gazebo Sim writes it, SDF 1.6 to 1.11, or a zros
YAML world; `empty.sdf` is the empty world) with no robot in it: robots come through
`ros_gz_sim create`. Like Gazebo Sim, it starts paused unless `-r` is given, and its topics
(`/clock`, the robots' sensors and drives) are on the Gazebo side (zros.sim.gz_topics): ROS nodes
see them only through `ros_gz_bridge`. Without `-s` it also opens the view (the GUI's role);
`-g` opens only the view. `--seed N` seeds the noise; `-v N`, `--force-version`, rendering,
physics and network options are accepted; the ones that would change the run are named in one
warning. Other `gz` commands (`gz topic`, `gz service`, ...) are not provided.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import zros
from zros.arguments import NodeArgumentParser, remove_ros_args
from zros.errors import CliError
from zros.executors import ExternalShutdownException, spin_nodes
from zros.parameter import Parameter

from nodes.turtlebot3_gazebo.gzserver import GazeboNode

__all__ = ['main', 'entry_point', 'sim_parameters', 'world_argument']

#: Gazebo Sim's options that take a value and change nothing in zros's simulator.
_ACCEPTED_WITH_VALUE = ('--force-version', '--render-engine', '--render-engine-gui', '--render-engine-server',
                        '--render-engine-gui-api-backend', '--render-engine-server-api-backend', '--gui-config')
#: ... and the ones whose effect zros does not model (named in the warning).
_IGNORED_WITH_VALUE = ('-z', '--iterations', '--physics-engine', '--network-role', '--network-secondaries',
                       '--record-path', '--record-period', '--playback', '--initial-sim-time', '--record-topic')
_ACCEPTED_FLAGS = ('--headless-rendering', '--wait-gui', '--levels')
_IGNORED_FLAGS = ('--record', '--log-overwrite', '--log-compress', '--record-resources')


def _parser() -> argparse.ArgumentParser:
    parser = NodeArgumentParser(prog='gz sim', description="Gazebo Sim, played by zros's 2D simulator")
    parser.add_argument('world', nargs='?', default='', help='world file (.sdf, or a zros .yaml world)')
    parser.add_argument('-r', action='store_true', help='run the simulation on start (else paused)')
    parser.add_argument('-s', action='store_true', help='server only, no GUI')
    parser.add_argument('-g', action='store_true', help='GUI only (the browser view)')
    parser.add_argument('-v', '--verbose', nargs='?', const='1', default='1', help='verbosity 0-4 (accepted)')
    parser.add_argument('--seed', type=int, help='random seed of every noise generator')
    for option in _ACCEPTED_WITH_VALUE + _IGNORED_WITH_VALUE:
        parser.add_argument(option, dest=f'opt{option}', metavar='VALUE', help=argparse.SUPPRESS)
    for flag in _ACCEPTED_FLAGS + _IGNORED_FLAGS:
        parser.add_argument(flag, dest=f'opt{flag}', action='store_true', help=argparse.SUPPRESS)
    return parser


def world_argument(world: str) -> str:
    """What the simulator loads for `gz sim WORLD`: the file if it exists, else the file of that
    name in a folder of GZ_SIM_RESOURCE_PATH, else `empty_world` for Gazebo's `empty.sdf`, else
    the name as given (zros's shipped world names; anything else is the world loader's one-line
    error)."""
    if not world or Path(world).is_file():
        return world
    for folder in filter(None, os.environ.get('GZ_SIM_RESOURCE_PATH', '').split(os.pathsep)):
        if (Path(folder) / world).is_file():
            return str(Path(folder) / world)
    return 'empty_world' if world in ('empty.sdf', 'empty') else world


def sim_parameters(argv: list[str]) -> tuple[argparse.Namespace, list[Parameter], list[str]]:
    """`gz sim ARGS` (`argv` after `sim`): the options, the simulator's parameters, and the given
    options whose effect zros does not model. CliError (one line) for a bad command line."""
    args = _parser().parse_args(argv)
    ignored = [option for option in _IGNORED_WITH_VALUE + _IGNORED_FLAGS
               if getattr(args, f'opt{option}') not in (None, False)]
    parameters = [Parameter('spawn_robot', value=False), Parameter('paused', value=not args.r)]
    if args.world:
        parameters.append(Parameter('world', value=world_argument(args.world)))
    if args.seed is not None:
        parameters.append(Parameter('seed', value=args.seed))
    return args, parameters, ignored


def _view() -> subprocess.Popen:
    return subprocess.Popen([sys.executable, '-m', 'zros', 'run', 'gazebo_ros', 'gzclient'], stdin=subprocess.DEVNULL)


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    command = remove_ros_args(argv)[1:]
    if not command or command[0] != 'sim':
        what = f"'gz {command[0]}'" if command else "'gz' without a command"
        raise CliError(f"{what}: zros plays only 'gz sim' (the simulator); 'zros topic', 'zros service' "
                       'show the rest')
    options, parameters, ignored = sim_parameters(command[1:])
    if options.g and not options.s:
        from nodes.gazebo_ros.gzclient import main as gzclient_main
        return gzclient_main([argv[0]])
    client = None if options.s else _view()
    try:
        with zros.init(args=argv):
            node = GazeboNode(gz=True, parameter_overrides=parameters)
            if ignored:
                node.get_logger().warn(f"gz sim: ignoring options zros does not model: {', '.join(ignored)}")
            spin_nodes(node, num_threads=4)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if client is not None:
            client.terminate()
            client.wait(timeout=5)
    return 0


def entry_point() -> None:
    """The `gz` command (pyproject's console script): `zros run ros_gz_sim gz ARGS`."""
    from zros.cli.main import entry_point as zros_entry_point
    zros_entry_point(['run', 'ros_gz_sim', 'gz', *sys.argv[1:]])


if __name__ == '__main__':
    sys.exit(main(sys.argv))
