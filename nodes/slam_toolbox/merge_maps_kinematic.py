"""merge_maps_kinematic: slam_toolbox's map merging tool, on zros's saved pose graphs.

    zros launch slam_toolbox merge_maps_kinematic_launch.py
    zros service call /slam_toolbox/add_submap slam_toolbox/srv/AddSubmap "{filename: /tmp/first}"
    zros service call /slam_toolbox/add_submap slam_toolbox/srv/AddSubmap "{filename: /tmp/second}"
    zros service call /slam_toolbox/merge_submaps slam_toolbox/srv/MergeMaps

`slam_toolbox/add_submap` (slam_toolbox/srv/AddSubmap) reads a graph written by serialize_map
(FILE.posegraph + FILE.data, zros.slam.serialization) and publishes its map on `/map_N` and
`/map_metadata_N` (N = 1, 2, ... in the order added); `slam_toolbox/merge_submaps`
(slam_toolbox/srv/MergeMaps) casts the scans of every submap into one grid and publishes it on
`/map` and `/map_metadata` (frame `map`, `resolution` m a cell). Maps are reliable and transient
local, so a late subscriber gets the last one.

What differs from slam_toolbox: its RViz interactive markers move each submap before merging;
zros has no interactive markers, so each submap stays where its own map frame puts it (submaps
made from the same start line up; slam_toolbox's untouched markers mean the same), and /map_N is
in frame `map` rather than a `map_N` frame of its own.
"""
from __future__ import annotations

import sys
from typing import Any

import zros
from zros.errors import CliError
from zros.executors import ExternalShutdownException, spin_nodes
from zros.map_io import map_to_msg
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile
from zros.slam import SlamParameters
from zros.slam.grid import occupancy_from_scans
from zros.slam.serialization import PoseGraphFileError, SerializedGraph, read_pose_graph

from interfaces.nav_msgs.msg import MapMetaData, OccupancyGrid
from interfaces.slam_toolbox.srv import AddSubmap, MergeMaps

__all__ = ['MergeMapsKinematic', 'main']

MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


class MergeMapsKinematic(Node):
    """Submaps in, one merged map out (module docstring)."""

    def __init__(self, node_name: str = 'map_merging', **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        resolution = self.declare_parameter('resolution', 0.05).value
        if not isinstance(resolution, (int, float)) or not resolution > 0:
            raise CliError(f"{self.get_name()}: parameter 'resolution' must be > 0 [m], got {resolution!r}")
        self._resolution = float(resolution)
        self._probabilities = SlamParameters()
        self._submaps: list[SerializedGraph] = []
        self._publishers: list[tuple[Any, Any]] = [self._map_publishers('')]
        self.create_service(AddSubmap, 'slam_toolbox/add_submap', self._on_add_submap)
        self.create_service(MergeMaps, 'slam_toolbox/merge_submaps', self._on_merge)
        self.get_logger().info('Ready: add submaps with slam_toolbox/add_submap, merge with slam_toolbox/merge_submaps')

    def _map_publishers(self, suffix: str) -> tuple[Any, Any]:
        return (self.create_publisher(OccupancyGrid, f'/map{suffix}', MAP_QOS),
                self.create_publisher(MapMetaData, f'/map_metadata{suffix}', MAP_QOS))

    def _publish(self, index: int, graphs: list[SerializedGraph]) -> None:
        p = self._probabilities
        poses = [pose for g in graphs for pose in g.poses]
        scans = [scan for g in graphs for scan in g.scans]
        grid = occupancy_from_scans(poses, scans, self._resolution, hit_probability=p.hit_probability,
                                    miss_probability=p.miss_probability, occupied_thresh=p.occupied_thresh,
                                    free_thresh=p.free_thresh)
        msg = map_to_msg(grid, frame_id='map', stamp=self.get_clock().now().to_msg())
        grid_pub, info_pub = self._publishers[index]
        grid_pub.publish(msg)
        info_pub.publish(msg.info)

    def _on_add_submap(self, request: Any, response: Any) -> Any:
        try:
            graph = read_pose_graph(request.filename)
        except PoseGraphFileError as exc:
            self.get_logger().error(f'add_submap failed: {exc}')
            return response
        self._submaps.append(graph)
        number = len(self._submaps)
        self._publishers.append(self._map_publishers(f'_{number}'))
        self._publish(number, [graph])
        self.get_logger().info(f'Map {request.filename} ({len(graph.poses)} nodes) was loaded into /map_{number}')
        return response

    def _on_merge(self, request: Any, response: Any) -> Any:
        if not self._submaps:
            self.get_logger().warn('merge_submaps: no submap added yet (slam_toolbox/add_submap)')
            return response
        self._publish(0, self._submaps)
        self.get_logger().info(f'Merged {len(self._submaps)} submaps into /map')
        return response


def main(args: list[str] | None = None) -> int:
    try:
        with zros.init(args=args):
            spin_nodes(MergeMapsKinematic())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main())
