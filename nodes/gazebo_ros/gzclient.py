"""gzclient: Gazebo's window, played by zros's browser view (zros_view view, fixed frame odom).

    gzclient                                   # Nav2's tb3_simulation_launch.py starts it so
    zros run gazebo_ros gzclient

Gazebo's client options (`--verbose`, `-g` plugins, ...) are accepted and have no effect. The
view logs the address to open; the simulator's robots, scans and TF show there.
"""
from __future__ import annotations

import sys

from zros.view.scene.node import run_view_node

__all__ = ['main', 'entry_point']


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    ros_args = argv[argv.index('--ros-args'):] if '--ros-args' in argv else []   # Gazebo's own options: none apply
    defaults = ['--ros-args', '-r', '__node:=gzclient', '-p', 'fixed_frame:=odom', '-p', 'use_sim_time:=true']
    return run_view_node('view', [argv[0], *defaults, *ros_args])


def entry_point() -> None:
    """The `gzclient` command (pyproject's console script): `zros run gazebo_ros gzclient ARGS`."""
    from zros.cli.main import entry_point as zros_entry_point
    zros_entry_point(['run', 'gazebo_ros', 'gzclient', *sys.argv[1:]])


if __name__ == '__main__':
    sys.exit(main(sys.argv))
