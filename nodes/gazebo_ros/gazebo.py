"""`gazebo`: Gazebo classic's all-in-one command (server and client), as Nav2's multi-robot launch
files start it (`ExecuteProcess(cmd=['gazebo', '--verbose', '-s', 'libgazebo_ros_init.so', ...,
world])`): gzserver runs in this process with the same arguments, gzclient (the browser view)
as a child that ends with it."""
from __future__ import annotations

import subprocess
import sys

from nodes.gazebo_ros.gzserver import main as gzserver_main


def main(args: list[str] | None = None) -> None:
    argv = list(sys.argv if args is None else args)
    client = subprocess.Popen([sys.executable, '-m', 'zros', 'run', 'gazebo_ros', 'gzclient'],
                              stdin=subprocess.DEVNULL)
    try:
        gzserver_main(argv)
    finally:
        client.terminate()
        try:
            client.wait(timeout=5)
        except subprocess.TimeoutExpired:
            client.kill()
            client.wait()


def entry_point() -> None:
    """The `gazebo` command (pyproject's console script): `zros run gazebo_ros gazebo ARGS`."""
    from zros.cli.main import entry_point as zros_entry_point
    zros_entry_point(['run', 'gazebo_ros', 'gazebo', *sys.argv[1:]])


if __name__ == '__main__':
    main(sys.argv)
