"""What every example does with its command line, kept out of the examples' `main()` as
zenoh-python keeps its examples' shared flags in their `common.py`: the example's own options
come before `--ros-args` and ROS's after it (`zros.init` reads those); Ctrl-C ends the program
quietly, as it ends ROS 2's demos."""
from __future__ import annotations

import argparse
import sys
from typing import Callable

from zros.executors import ExternalShutdownException
from zros.utilities import remove_ros_args

__all__ = ['parse_args', 'run']


def parse_args(parser: argparse.ArgumentParser) -> argparse.Namespace:
    """The example's own options: the command line without the `--ros-args` part."""
    return parser.parse_args(remove_ros_args(sys.argv)[1:])


def run(main: Callable[..., int | None], *args: object) -> None:
    """Call `main(*args, sys.argv)` and exit with what it returns (None: 0). Ctrl-C, or a
    shutdown from elsewhere (SIGTERM, `zros.shutdown()`), exits with 0."""
    try:
        status = main(*args, sys.argv)
    except (KeyboardInterrupt, ExternalShutdownException):
        status = 0
    sys.exit(status)
