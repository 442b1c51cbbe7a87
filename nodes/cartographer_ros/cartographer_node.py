"""`cartographer_ros cartographer_node`: zros's SLAM configured from Cartographer's Lua file
(package docstring)."""
from __future__ import annotations

import argparse
import os
import sys

import zros
from zros.errors import CliError
from zros.executors import ExternalShutdownException, spin_nodes
from zros.parameter import Parameter
from zros.slam.cartographer_lua import LuaConfigError, read_options, slam_parameters
from zros.utilities import remove_ros_args

from nodes.slam_toolbox.async_slam_toolbox_node import SlamNode


def _arguments(argv: list[str]) -> argparse.Namespace:
    """Cartographer's gflags, single dash, as its launch files pass them."""
    parser = argparse.ArgumentParser(prog='cartographer_node', add_help=False, allow_abbrev=False)
    parser.add_argument('-configuration_directory', required=True)
    parser.add_argument('-configuration_basename', required=True)
    for accepted in ('-load_state_filename', '-save_state_filename', '-load_frozen_state', '-collect_metrics',
                     '-start_trajectory_with_default_topics'):
        parser.add_argument(accepted)
    arguments, unknown = parser.parse_known_args(argv)
    if unknown:
        raise CliError(f"cartographer_node: unknown arguments {' '.join(unknown)}")
    return arguments


def main(args: list[str] | None = None) -> int:
    argv = remove_ros_args(args if args is not None else sys.argv)[1:]
    try:
        arguments = _arguments(argv)
    except SystemExit:
        raise CliError('cartographer_node: usage: cartographer_node -configuration_directory DIR '
                       '-configuration_basename FILE.lua') from None
    try:
        options = read_options(os.path.join(arguments.configuration_directory, arguments.configuration_basename))
    except LuaConfigError as exc:
        raise CliError(f'cartographer_node: {exc}') from None
    overrides = [Parameter(name, value=value) for name, value in slam_parameters(options).items()]
    try:
        with zros.init(args=args):
            spin_nodes(SlamNode('cartographer_node', publish_map=False, parameter_overrides=overrides))
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
