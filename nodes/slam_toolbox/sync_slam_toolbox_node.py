"""sync_slam_toolbox_node: slam_toolbox's synchronous executable name (online_sync_launch.py,
nav2_bringup's slam:=True). zros has one SLAM node: this is async_slam_toolbox_node, which
drops no scan it can keep up with (docs/slam.md)."""
from __future__ import annotations

import sys

from nodes.slam_toolbox.async_slam_toolbox_node import main

__all__ = ['main']

if __name__ == '__main__':
    sys.exit(main())
