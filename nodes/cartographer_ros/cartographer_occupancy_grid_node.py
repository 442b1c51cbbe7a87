"""`cartographer_ros cartographer_occupancy_grid_node`: /map every `-publish_period_sec` seconds at
`-resolution` metres a cell, from cartographer_node's map (package docstring)."""
from __future__ import annotations

import argparse
import sys
from typing import Any

import numpy as np

import zros
from zros.errors import CliError
from zros.executors import ExternalShutdownException, spin_nodes
from zros.map_io import map_from_msg, map_to_msg, resample
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile
from zros.utilities import remove_ros_args

from interfaces.nav_msgs.msg import OccupancyGrid
from interfaces.nav_msgs.srv import GetMap

MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class OccupancyGridNode(Node):
    """Asks `cartographer_node/dynamic_map` for the map each period; publishes it when it changed."""

    def __init__(self, resolution: float, period: float) -> None:
        super().__init__('cartographer_occupancy_grid_node')
        self._resolution = resolution
        self._client = self.create_client(GetMap, 'cartographer_node/dynamic_map')
        self._publisher = self.create_publisher(OccupancyGrid, 'map', MAP_QOS)
        self._pending: Any = None
        self._last: bytes | None = None
        self.create_timer(period, self._request)

    def _request(self) -> None:
        if self._pending is not None or not self._client.service_is_ready():
            return
        self._pending = self._client.call_async(GetMap.Request())
        self._pending.add_done_callback(self._on_map)

    def _on_map(self, future: Any) -> None:
        self._pending = None
        response = future.result()
        if response is None or not (np.asarray(response.map.data) != -1).any():
            return   # no submap yet: Cartographer's node publishes nothing until there is one
        grid = resample(map_from_msg(response.map), self._resolution)
        cells = grid.data.tobytes()
        if cells == self._last:
            return
        self._last = cells
        self._publisher.publish(map_to_msg(grid, frame_id=response.map.header.frame_id or 'map',
                                           stamp=self.get_clock().now().to_msg()))


def main(args: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='cartographer_occupancy_grid_node', add_help=False, allow_abbrev=False)
    parser.add_argument('-resolution', type=float, default=0.05)
    parser.add_argument('-publish_period_sec', type=float, default=1.0)
    parser.add_argument('-include_frozen_submaps', default=None)
    parser.add_argument('-include_unfrozen_submaps', default=None)
    try:
        arguments = parser.parse_args(remove_ros_args(args if args is not None else sys.argv)[1:])
    except SystemExit:
        raise CliError('cartographer_occupancy_grid_node: usage: -resolution METRES -publish_period_sec SECONDS') from None
    if not arguments.resolution > 0 or not arguments.publish_period_sec > 0:
        raise CliError('cartographer_occupancy_grid_node: -resolution and -publish_period_sec must be > 0')
    try:
        with zros.init(args=args):
            spin_nodes(OccupancyGridNode(arguments.resolution, arguments.publish_period_sec), num_threads=2)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
