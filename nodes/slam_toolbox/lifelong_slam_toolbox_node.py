"""lifelong_slam_toolbox_node: slam_toolbox's lifelong mapping executable (lifelong_launch.py).
Lifelong mapping is mapping that goes on in a saved map: async_slam_toolbox_node loads
`map_file_name` (at `map_start_pose` or its first node with `map_start_at_dock`) and adds the new
keyframes to the old graph, closing loops into it. slam_toolbox's node pruning
(`lifelong_node_removal_score` & co.) is not done: the graph only grows (docs/slam.md)."""
from __future__ import annotations

import sys

from nodes.slam_toolbox.async_slam_toolbox_node import main

__all__ = ['main']

if __name__ == '__main__':
    sys.exit(main())
