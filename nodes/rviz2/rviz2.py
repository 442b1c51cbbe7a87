"""rviz2: `zros run rviz2 rviz2 [-d file.rviz] [-f frame]` opens the scene view (zros.view.scene).

The displays, fixed frame, grid and camera come from the `.rviz` file; the page's URL is logged
(http://127.0.0.1:8080/, or the next free port). A launch file's
`Node(package='rviz2', executable='rviz2', arguments=['-d', cfg])` starts the same thing.
"""
from __future__ import annotations

import sys

from zros.view.scene.node import run_view_node

__all__ = ['main']


def main(args: list[str] | None = None) -> int:
    return run_view_node('rviz2', args if args is not None else sys.argv)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
