"""view: the zros scene view as a node (`zros run zros_view view`), for launch files.

Serves the scene view (zros.view.scene: the 3D scene, displays, tools, topics, graph, console
and images) and logs its URL. Parameters (read at start): config ('' or a .rviz / zros view
file), fixed_frame, port (8080: the next free port up to 8089 is taken if it is busy; 0 = any),
host (127.0.0.1: this machine only), topic (an image topic to show first, e.g.
/turtlesim/image). `zros view` is the same thing as a CLI verb.
"""
from __future__ import annotations

import sys

from zros.view.scene.node import run_view_node

__all__ = ['main']


def main(args: list[str] | None = None) -> int:
    return run_view_node('view', args if args is not None else sys.argv)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
